// Unit conversions shared by all packages: rpm <-> rad/s, degrees <-> radians, m <-> mm, hours, g.
#pragma once

namespace flagella::units {

inline constexpr double pi = 3.14159265358979323846;  // the value of M_PI

inline constexpr double kRadPerSecPerRpm = 2.0 * pi / 60.0;
inline constexpr double kRpmPerRadPerSec = 60.0 / (2.0 * pi);
inline constexpr double kSecondsPerHour = 3600.0;
inline constexpr double kMetresPerMm = 1e-3;
inline constexpr double kStandardGravity = 9.80665;  // [m/s^2], the g of sensor data sheets

constexpr double rpmToRadPerSec(double rpm) { return rpm * kRadPerSecPerRpm; }
constexpr double radPerSecToRpm(double rad_per_sec) { return rad_per_sec * kRpmPerRadPerSec; }

constexpr double degToRad(double deg) { return deg * pi / 180.0; }
constexpr double radToDeg(double rad) { return rad * 180.0 / pi; }

constexpr double metresToMm(double metres) { return metres * 1e3; }
constexpr double mmToMetres(double mm) { return mm * kMetresPerMm; }

}  // namespace flagella::units
