// Measured-data files: CSV + YAML metadata readers and writers (ROS-free part).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "../../flagella_sim/test/support/temp_dir.h"
#include "flagella_identify/data_io.h"
#include "flagella_sim/core/units.h"

namespace flagella::identify {
namespace {

using flagella::testing::errorMessageOf;
using flagella::testing::TempDir;

/// The message thrown by readMeasuredData(path) (a DataError expected).
std::string readError(const std::string& path) {
  return errorMessageOf<DataError>([&] { readMeasuredData(path); });
}

/// True if `message` starts with `prefix`, with a readable failure otherwise.
::testing::AssertionResult startsWith(const std::string& message, const std::string& prefix) {
  if (message.compare(0, prefix.size(), prefix) == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "message\n  " << message << "\ndoes not start with\n  " << prefix;
}

const char* kTableYaml =
    "kind: steady_state\n"
    "csv: t.csv\n"
    "noise:\n"
    "  v_mm_s: 0.003\n"
    "  omega_h_rpm: 0.5\n";

// A valid time series whose CSV the malformed-input cases replace.
const char* kSeriesYaml =
    "kind: time_series\n"
    "csv: s.csv\n"
    "noise:\n"
    "  position_mm: 0.3\n"
    "  orientation_rad: 0.01\n"
    "  turns: 0.25\n";

// ------------------------------------------------------------------------------ reading

TEST(DataIo, SteadyOutputNamesInDocumentedOrder) {
  EXPECT_EQ(steadyOutputNames(), (std::vector<std::string>{"v", "omega_h", "omega_t", "omega_yr",
                                                           "R_yr", "buckling_threshold", "tilt"}));
}

// The flagellum's tilt in degrees (docs/model.md 8.4.4) is stored in radians; 0-180 deg.
TEST(DataIo, TiltColumnInDegrees) {
  TempDir dir;
  dir.write("t.csv", "omega_T_rpm, v_mm_s, tilt_deg\n40, 1.1, 1.5\n80, 2.2, \n");
  const std::string yaml = dir.write(
      "t.yaml", "kind: steady_state\ncsv: t.csv\nnoise: {v_mm_s: 0.003, tilt_deg: 0.2}\n");
  const MeasuredData data = readMeasuredData(yaml);
  const SteadyStateTable& t = data.tables.at(0);
  EXPECT_NEAR(t.rows[0].measured.at("tilt"), 1.5 * units::pi / 180.0, 1e-15);
  EXPECT_TRUE(std::isnan(t.rows[1].measured.at("tilt")));
  EXPECT_NEAR(t.noise.at("tilt"), 0.2 * units::pi / 180.0, 1e-15);
  const std::string csv = dir.write("u.csv", "omega_T_rpm, tilt_deg\n40, 190\n");
  const std::string bad =
      dir.write("u.yaml", "kind: steady_state\ncsv: u.csv\nnoise: {tilt_deg: 0.2}\n");
  const std::string message = readError(bad);
  EXPECT_TRUE(startsWith(message, csv + ":2:2:")) << message;
  EXPECT_NE(message.find("180"), std::string::npos) << message;
}

TEST(DataIo, ThresholdTableNeedsNoMotorSpeed) {
  TempDir dir;
  dir.write("g.csv",
            "id, robot.filament_radius, buckling_threshold_rpm\n"
            "thin, 1.188e-3, 4.53\n"
            "thick, 3.168e-3, 45.9\n");
  const MeasuredData data = readMeasuredData(dir.write(
      "g.yaml", "kind: steady_state\ncsv: g.csv\nnoise: {buckling_threshold_rpm: 0.2}\n"));
  const SteadyStateTable& t = data.tables.at(0);
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[1].omega_T, 0.0);
  EXPECT_NEAR(t.rows[1].measured.at("buckling_threshold"), units::rpmToRadPerSec(45.9), 1e-12);
  EXPECT_NEAR(t.noise.at("buckling_threshold"), units::rpmToRadPerSec(0.2), 1e-12);
  EXPECT_EQ(t.rows[0].overrides,
            (std::vector<ConfigOverride>{{"robot.filament_radius", "1.188e-3"}}));
  // with a steady-state output beside the threshold, the motor speed is required again
  const std::string csv = dir.write("h.csv", "v_mm_s,buckling_threshold_rpm\n0.3,5\n");
  const std::string yaml = dir.write(
      "h.yaml",
      "kind: steady_state\ncsv: h.csv\nnoise: {v_mm_s: 0.01, buckling_threshold_rpm: 0.2}\n");
  EXPECT_TRUE(startsWith(readError(yaml), csv + ":1:1: missing required column 'omega_T_rpm'"));
}

TEST(DataIo, SteadyStateTableIsConvertedToSi) {
  TempDir dir;
  std::filesystem::create_directories(dir.path() / "tables");
  dir.write("tables/d1.csv",
            "# design 1, tank A\n"
            "id, time_s, omega_T_rpm, v_mm_s, omega_h_rpm, omega_t_rpm, omega_yr_rad_s, R_yr_mm, "
            "robot.n_tails, robot.tail_angles\n"
            "\n"
            "a1, 12.5, 60, 1.5, 30, -120, 0.25, 250, 3, \"[0, 2.0944, 4.1888]\"\n"
            "  # a comment between rows\n"
            "a2, , -30, 2, , 6, 0.5, 100, , \n");
  const std::string yaml = dir.write("tables/d1.yaml",
                                     "kind: steady_state\n"
                                     "csv: d1.csv\n"
                                     "description: \"design 1, tank A\"\n"
                                     "settle_time_s: 5\n"
                                     "window_s: 30\n"
                                     "overrides:\n"
                                     "  robot.tail_edges: 10\n"
                                     "  medium.viscosity: 0.97\n"
                                     "noise:\n"
                                     "  v_mm_s: 0.003\n"
                                     "  omega_h_rpm: 0.5\n"
                                     "  omega_t_rpm: 0.2\n"
                                     "  omega_yr_rad_s: 0.01\n"
                                     "  R_yr_mm: 2\n");
  const MeasuredData data = readMeasuredData(yaml);
  ASSERT_EQ(data.tables.size(), 1u);
  EXPECT_TRUE(data.series.empty());
  const SteadyStateTable& t = data.tables[0];
  EXPECT_EQ(t.source, yaml);
  EXPECT_EQ(t.description, "design 1, tank A");
  EXPECT_DOUBLE_EQ(t.settle_time, 5.0);
  EXPECT_DOUBLE_EQ(t.window, 30.0);
  EXPECT_EQ(t.overrides, (std::vector<ConfigOverride>{{"robot.tail_edges", "10"},
                                                      {"medium.viscosity", "0.97"}}));
  EXPECT_DOUBLE_EQ(t.noise.at("v"), 3e-6);
  EXPECT_DOUBLE_EQ(t.noise.at("omega_h"), units::rpmToRadPerSec(0.5));
  EXPECT_DOUBLE_EQ(t.noise.at("omega_t"), units::rpmToRadPerSec(0.2));
  EXPECT_DOUBLE_EQ(t.noise.at("omega_yr"), 0.01);
  EXPECT_DOUBLE_EQ(t.noise.at("R_yr"), 2e-3);
  ASSERT_EQ(t.rows.size(), 2u);
  const SteadyStateRow& a = t.rows[0];
  EXPECT_EQ(a.line, 4);
  EXPECT_EQ(a.id, "a1");
  EXPECT_DOUBLE_EQ(a.time, 12.5);
  EXPECT_NEAR(a.omega_T, 2 * units::pi, 1e-12);  // 60 rpm = 1 turn per second
  EXPECT_NEAR(a.measured.at("v"), 1.5e-3, 1e-15);
  EXPECT_NEAR(a.measured.at("omega_h"), units::pi, 1e-12);  // 30 rpm = pi rad/s
  EXPECT_NEAR(a.measured.at("omega_t"), -4 * units::pi, 1e-12);
  EXPECT_DOUBLE_EQ(a.measured.at("omega_yr"), 0.25);
  EXPECT_NEAR(a.measured.at("R_yr"), 0.25, 1e-15);
  EXPECT_EQ(a.overrides,
            (std::vector<ConfigOverride>{{"robot.n_tails", "3"},
                                         {"robot.tail_angles", "[0, 2.0944, 4.1888]"}}));
  const SteadyStateRow& b = t.rows[1];
  EXPECT_EQ(b.line, 6);
  EXPECT_NEAR(b.omega_T, -units::pi, 1e-12);
  EXPECT_NEAR(b.measured.at("omega_t"), 0.2 * units::pi, 1e-12);  // 6 rpm
}

TEST(DataIo, SteadyStateDefaultsAndMissingValues) {
  TempDir dir;
  dir.write("t.csv",
            "omega_T_rpm,v_mm_s,omega_h_rpm,time_s,robot.n_tails\n"
            "100,,5,,\n"
            "-100,2.5,,3,2\n");
  const MeasuredData data = readMeasuredData(dir.write("t.yaml", kTableYaml));
  const SteadyStateTable& t = data.tables.at(0);
  EXPECT_DOUBLE_EQ(t.settle_time, 10.0);
  EXPECT_DOUBLE_EQ(t.window, 20.0);
  EXPECT_EQ(t.description, "");
  EXPECT_TRUE(t.overrides.empty());
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_TRUE(std::isnan(t.rows[0].measured.at("v")));
  EXPECT_NEAR(t.rows[0].measured.at("omega_h"), units::rpmToRadPerSec(5.0), 1e-12);
  EXPECT_TRUE(std::isnan(t.rows[0].time));
  EXPECT_TRUE(t.rows[0].overrides.empty());
  EXPECT_EQ(t.rows[0].id, "");
  EXPECT_NEAR(t.rows[1].measured.at("v"), 2.5e-3, 1e-15);
  EXPECT_TRUE(std::isnan(t.rows[1].measured.at("omega_h")));
  EXPECT_EQ(t.rows[1].measured.count("omega_t"), 0u);  // column absent: not in the map
  EXPECT_DOUBLE_EQ(t.rows[1].time, 3.0);
  EXPECT_EQ(t.rows[1].overrides, (std::vector<ConfigOverride>{{"robot.n_tails", "2"}}));
}

TEST(DataIo, TimeSeriesIsConvertedToSi) {
  TempDir dir;
  dir.write("s.csv",
            "t_s,x_mm,y_mm,z_mm,qw,qx,qy,qz,head_turns,tail_turns,omega_T_rpm\n"
            "0,1,2,3,1,0,0,0,0,0,60\n"
            "0.5,10,-20,30,0,0,0,1,0.25,-0.5,120\n"
            "1,100,200,-300,0.5,0.5,0.5,0.5,0.5,-1,-60\n");
  const std::string yaml = dir.write("s.yaml",
                                     "kind: time_series\n"
                                     "csv: s.csv\n"
                                     "description: run 1\n"
                                     "session_time_s: 600\n"
                                     "overrides: {robot.n_tails: 2, robot.tail_angles: [0, 3.14]}\n"
                                     "noise:\n"
                                     "  position_mm: 0.3\n"
                                     "  orientation_rad: 0.01\n"
                                     "  turns: 0.25\n");
  const MeasuredData data = readMeasuredData(yaml);
  ASSERT_EQ(data.series.size(), 1u);
  const TimeSeries& s = data.series[0];
  EXPECT_EQ(s.source, yaml);
  EXPECT_EQ(s.description, "run 1");
  EXPECT_DOUBLE_EQ(s.session_time, 600.0);
  EXPECT_EQ(s.overrides, (std::vector<ConfigOverride>{{"robot.n_tails", "2"},
                                                      {"robot.tail_angles", "[0, 3.14]"}}));
  EXPECT_EQ(s.t, (std::vector<double>{0, 0.5, 1}));
  EXPECT_TRUE(s.has_z);
  ASSERT_EQ(s.position.size(), 3u);
  EXPECT_NEAR((s.position[1] - Vec3(0.01, -0.02, 0.03)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((s.position[2] - Vec3(0.1, 0.2, -0.3)).norm(), 0.0, 1e-15);
  ASSERT_EQ(s.orientation.size(), 3u);
  EXPECT_DOUBLE_EQ(s.orientation[0].w(), 1.0);
  EXPECT_DOUBLE_EQ(s.orientation[1].z(), 1.0);
  EXPECT_DOUBLE_EQ(s.orientation[2].x(), 0.5);
  EXPECT_EQ(s.head_turns, (std::vector<double>{0, 0.25, 0.5}));
  EXPECT_EQ(s.tail_turns, (std::vector<double>{0, -0.5, -1}));
  ASSERT_EQ(s.omega_cmd.size(), 3u);
  EXPECT_NEAR(s.omega_cmd[0], 2 * units::pi, 1e-12);
  EXPECT_NEAR(s.omega_cmd[1], 4 * units::pi, 1e-12);
  EXPECT_NEAR(s.omega_cmd[2], -2 * units::pi, 1e-12);
  EXPECT_DOUBLE_EQ(s.position_noise, 3e-4);
  EXPECT_DOUBLE_EQ(s.orientation_noise, 0.01);
  EXPECT_DOUBLE_EQ(s.turns_noise, 0.25);
}

TEST(DataIo, TimeSeriesWithoutOptionalColumns) {
  TempDir dir;
  dir.write("s.csv",
            "omega_T_rpm, t_s, y_mm, x_mm\n"  // any column order
            "30, 1.0, 2, 1\n"
            "30, 1.1, 3, 1\n"
            "30, 1.2, 4, 1\n");
  const MeasuredData data = readMeasuredData(dir.write("s.yaml",
                                                       "kind: time_series\n"
                                                       "csv: s.csv\n"
                                                       "noise: {position_mm: 0.5}\n"));
  const TimeSeries& s = data.series.at(0);
  EXPECT_FALSE(s.has_z);
  EXPECT_TRUE(std::isnan(s.position[0].z()));  // not measured
  EXPECT_DOUBLE_EQ(s.position[2].x(), 1e-3);
  EXPECT_DOUBLE_EQ(s.position[2].y(), 4e-3);
  EXPECT_DOUBLE_EQ(s.t[0], 1.0);  // times are kept as written
  EXPECT_TRUE(s.orientation.empty());
  EXPECT_TRUE(s.head_turns.empty());
  EXPECT_TRUE(s.tail_turns.empty());
  EXPECT_DOUBLE_EQ(s.session_time, 0.0);
  EXPECT_DOUBLE_EQ(s.position_noise, 5e-4);
  EXPECT_DOUBLE_EQ(s.orientation_noise, 0.0);
}

TEST(DataIo, SeveralFilesAreMerged) {
  TempDir dir;
  dir.write("t.csv", "omega_T_rpm,v_mm_s\n60,1\n");
  dir.write("s.csv", "t_s,x_mm,y_mm,omega_T_rpm\n0,0,0,1\n1,1,0,1\n2,2,0,1\n");
  const std::string table = dir.write("t.yaml", kTableYaml);
  const std::string series =
      dir.write("s.yaml", "kind: time_series\ncsv: s.csv\nnoise: {position_mm: 1}\n");
  const MeasuredData data = readMeasuredData(std::vector<std::string>{table, series, table});
  EXPECT_EQ(data.tables.size(), 2u);
  EXPECT_EQ(data.series.size(), 1u);
}

TEST(DataIo, BagMetadataWithoutTheBagLibraryIsAnError) {
  ASSERT_FALSE(bagReaderRegistered());
  TempDir dir;
  dir.write("run.bag", "not read");
  const std::string yaml = dir.write("b.yaml",
                                     "kind: time_series\n"
                                     "bag: run.bag\n"
                                     "noise: {position_mm: 1}\n");
  const std::string message = readError(yaml);
  EXPECT_TRUE(startsWith(message, yaml + ":2:6: "));
  EXPECT_NE(message.find("flagella_identify_bag"), std::string::npos) << message;
}

// ------------------------------------------------------------------------------ round trips

TEST(DataIo, PerRowUncertaintyOverridesTheTableNoise) {
  // Speed only, with its own uncertainty in some rows; rows of two tail counts in one table.
  TempDir dir;
  dir.write("t.csv",
            "omega_T_rpm,v_mm_s,sigma_v_mm_s,robot.n_tails\n"
            "100,1.5,0.02,2\n"
            "150,2.5,,3\n");
  const MeasuredData data = readMeasuredData(
      dir.write("t.yaml", "kind: steady_state\ncsv: t.csv\nnoise:\n  v_mm_s: 0.003\n"));
  const SteadyStateTable& t = data.tables.at(0);
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_NEAR(t.rows[0].sigmaOf("v", t.noise), 2e-5, 1e-18);  // mm/s -> m/s
  EXPECT_NEAR(t.rows[1].sigmaOf("v", t.noise), 3e-6, 1e-18);  // the table's
  EXPECT_TRUE(std::isnan(t.rows[1].sigmaOf("omega_h", t.noise)));
  EXPECT_EQ(t.rows[1].overrides, (std::vector<ConfigOverride>{{"robot.n_tails", "3"}}));
  // Every row with its own: the metadata needs no noise for the column.
  dir.write("u.csv", "omega_T_rpm,omega_h_rpm,sigma_omega_h_rpm\n100,5,0.4\n120,,\n");
  const MeasuredData rates_only =
      readMeasuredData(dir.write("u.yaml", "kind: steady_state\ncsv: u.csv\n"));
  EXPECT_NEAR(rates_only.tables[0].rows[0].sigmaOf("omega_h", rates_only.tables[0].noise),
              units::rpmToRadPerSec(0.4), 1e-15);
}

TEST(DataIoErrors, PerRowUncertaintyProblems) {
  TempDir dir;
  const char* bare = "kind: steady_state\ncsv: t.csv\n";
  dir.write("t.csv", "omega_T_rpm,v_mm_s,sigma_v_mm_s\n100,1.5,0.02\n150,2.5,\n");
  const std::string yaml = dir.write("t.yaml", bare);
  EXPECT_TRUE(startsWith(readError(yaml), dir.path().string() + "/t.csv:3:2: 'v_mm_s' has no "
                                                                "uncertainty in this row"))
      << readError(yaml);
  dir.write("t.csv", "omega_T_rpm,v_mm_s,sigma_v_mm_s\n100,1.5,0\n");
  EXPECT_NE(readError(yaml).find("column 'sigma_v_mm_s': 0 mm/s is outside the plausible range"),
            std::string::npos)
      << readError(yaml);
  dir.write("t.csv", "omega_T_rpm,v_mm_s,sigma_omega_h_rpm\n100,1.5,0.5\n");
  const std::string with_noise =
      dir.write("n.yaml", "kind: steady_state\ncsv: t.csv\nnoise:\n  v_mm_s: 0.003\n");
  EXPECT_TRUE(startsWith(readError(with_noise), dir.path().string() +
                                                    "/t.csv:1:3: column 'sigma_omega_h_rpm' gives "
                                                    "the uncertainty of 'omega_h_rpm', which the "
                                                    "table does not have"))
      << readError(with_noise);
}

TEST(DataIo, PerRowUncertaintyRoundTrip) {
  SteadyStateTable t;
  t.settle_time = 5.0;
  t.window = 10.0;
  t.noise = {{"omega_h", 0.05}};
  for (int i = 0; i < 3; ++i) {
    SteadyStateRow r;
    r.omega_T = 10.0 * (i + 1);
    r.measured["v"] = 1e-3 * (i + 1);
    r.sigma["v"] = 2e-6 * (i + 1);  // speed: every row its own, no table noise
    r.measured["omega_h"] = -0.5 * i;
    if (i == 1) r.sigma["omega_h"] = 0.2;  // one row overrides the table's
    t.rows.push_back(r);
  }
  TempDir dir;
  const std::string yaml = (dir.path() / "table.yaml").string();
  writeSteadyStateTable(t, yaml);
  const SteadyStateTable u = readMeasuredData(yaml).tables.at(0);
  ASSERT_EQ(u.rows.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    for (const char* output : {"v", "omega_h"})
      EXPECT_NEAR(u.rows[i].sigmaOf(output, u.noise), t.rows[i].sigmaOf(output, t.noise),
                  1e-9 * t.rows[i].sigmaOf(output, t.noise))
          << i << " " << output;
    EXPECT_EQ(u.rows[i].sigma.size(), t.rows[i].sigma.size()) << i;
  }
  // A measured value with no uncertainty at all cannot be written.
  t.rows[2].sigma.erase("v");
  EXPECT_NE(errorMessageOf<DataError>([&] {
              writeSteadyStateTable(t, yaml);
            }).find("no noise for measured output 'v'"),
            std::string::npos);
}

TEST(DataIo, SteadyStateTableRoundTrip) {
  SteadyStateTable t;
  t.description = "design 2: \"quoted\", with commas";
  t.settle_time = 7.25;
  t.window = 12.125;
  t.overrides = {{"robot.tail_edges", "12"}, {"robot.tail_angles", "[0, 1.5707963]"}};
  t.noise = {{"v", 2.5e-6}, {"omega_h", 0.0523598776}, {"R_yr", 1e-3}};
  for (int i = 0; i < 4; ++i) {
    SteadyStateRow r;
    r.id = i == 1 ? "" : "run, " + std::to_string(i);
    r.omega_T = (i - 1.5) * 12.3456789012345;
    r.time = i == 2 ? kMissing : 100.0 / 3.0 * i;
    r.measured["v"] = 1.23456789012345e-3 * (i + 1);
    r.measured["omega_h"] = i == 3 ? kMissing : -0.987654321098765 * i;
    r.measured["R_yr"] = 0.1234567890123 / (i + 1);
    if (i % 2 == 0) r.overrides.emplace_back("robot.n_tails", std::to_string(i + 1));
    if (i == 3) r.overrides.emplace_back("medium.viscosity", "1.5e-3");
    t.rows.push_back(r);
  }
  TempDir dir;
  const std::string yaml = (dir.path() / "table.yaml").string();
  writeSteadyStateTable(t, yaml);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "table.csv"));
  const MeasuredData data = readMeasuredData(yaml);
  ASSERT_EQ(data.tables.size(), 1u);
  const SteadyStateTable& u = data.tables[0];
  const auto close = [](double a, double b) {
    return (std::isnan(a) && std::isnan(b)) || std::abs(a - b) <= 1e-9 * std::abs(b);
  };
  EXPECT_EQ(u.source, yaml);
  EXPECT_EQ(u.description, t.description);
  EXPECT_TRUE(close(u.settle_time, t.settle_time));
  EXPECT_TRUE(close(u.window, t.window));
  EXPECT_EQ(u.overrides, t.overrides);
  ASSERT_EQ(u.noise.size(), t.noise.size());
  for (const auto& [name, sigma] : t.noise) EXPECT_TRUE(close(u.noise.at(name), sigma)) << name;
  ASSERT_EQ(u.rows.size(), t.rows.size());
  for (size_t i = 0; i < t.rows.size(); ++i) {
    const SteadyStateRow& a = t.rows[i];
    const SteadyStateRow& b = u.rows[i];
    EXPECT_EQ(b.line, static_cast<int>(i) + 2);
    EXPECT_EQ(b.id, a.id);
    EXPECT_TRUE(close(b.omega_T, a.omega_T)) << i;
    EXPECT_TRUE(close(b.time, a.time)) << i;
    EXPECT_EQ(b.overrides, a.overrides) << i;
    ASSERT_EQ(b.measured.size(), a.measured.size());
    for (const auto& [name, value] : a.measured)
      EXPECT_TRUE(close(b.measured.at(name), value)) << i << " " << name;
  }
}

TEST(DataIo, TimeSeriesRoundTrip) {
  for (const bool full : {true, false}) {
    SCOPED_TRACE(full ? "all columns" : "required columns only");
    TimeSeries s;
    s.description = "run: 7";
    s.session_time = 1234.5678901;
    s.overrides = {{"robot.n_tails", "4"}};
    s.has_z = full;
    s.position_noise = 3.3e-4;
    s.orientation_noise = full ? 0.0123 : 0.0;
    s.turns_noise = full ? 0.2 : 0.0;
    for (int i = 0; i < 25; ++i) {
      const double t = 0.1 * i + 1e-7 * i * i;
      s.t.push_back(t);
      s.position.emplace_back(0.0123456789 * std::sin(t), -0.00987654321 * t,
                              full ? 1e-4 * std::cos(3 * t) : kMissing);
      if (full) {
        s.orientation.push_back(
            Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * t, Vec3(1, 2, 3).normalized())));
        s.head_turns.push_back(1.23456789 * t);
        s.tail_turns.push_back(-0.456789123 * t);
      }
      s.omega_cmd.push_back(i < 10 ? 12.566370614359172 : -31.41592653589793);
    }
    TempDir dir;
    const std::string yaml = (dir.path() / "run.yaml").string();
    writeTimeSeries(s, yaml);
    const TimeSeries u = readMeasuredData(yaml).series.at(0);
    const auto close = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::abs(b); };
    EXPECT_EQ(u.description, s.description);
    EXPECT_TRUE(close(u.session_time, s.session_time));
    EXPECT_EQ(u.overrides, s.overrides);
    EXPECT_EQ(u.has_z, s.has_z);
    EXPECT_TRUE(close(u.position_noise, s.position_noise));
    EXPECT_TRUE(close(u.orientation_noise, s.orientation_noise));
    EXPECT_TRUE(close(u.turns_noise, s.turns_noise));
    ASSERT_EQ(u.t.size(), s.t.size());
    ASSERT_EQ(u.orientation.size(), s.orientation.size());
    ASSERT_EQ(u.head_turns.size(), s.head_turns.size());
    ASSERT_EQ(u.tail_turns.size(), s.tail_turns.size());
    for (size_t i = 0; i < s.t.size(); ++i) {
      EXPECT_TRUE(close(u.t[i], s.t[i])) << i;
      for (int k = 0; k < (full ? 3 : 2); ++k)
        EXPECT_TRUE(close(u.position[i](k), s.position[i](k))) << i << " " << k;
      if (!full) {
        EXPECT_TRUE(std::isnan(u.position[i].z()));
      } else {
        EXPECT_LT(u.orientation[i].angularDistance(s.orientation[i]), 1e-9) << i;
        EXPECT_TRUE(close(u.head_turns[i], s.head_turns[i])) << i;
        EXPECT_TRUE(close(u.tail_turns[i], s.tail_turns[i])) << i;
      }
      EXPECT_TRUE(close(u.omega_cmd[i], s.omega_cmd[i])) << i;
    }
  }
}

/// A table of one row that measures v at 1 rad/s, with no noise given.
SteadyStateTable oneRowTable() {
  SteadyStateTable t;
  t.settle_time = 10;
  t.window = 20;
  SteadyStateRow r;
  r.omega_T = 1.0;
  r.measured["v"] = 1e-3;
  t.rows.push_back(r);
  return t;
}

TEST(DataIo, WritersRejectDataThatCouldNotBeReadBack) {
  TempDir dir;
  const std::string yaml = (dir.path() / "w.yaml").string();
  SteadyStateTable t = oneRowTable();
  EXPECT_TRUE(
      startsWith(errorMessageOf<DataError>([&] { writeSteadyStateTable(t, yaml); }),
                 yaml + ": cannot write the steady-state table: no noise for measured output 'v'"));
  t.noise["v"] = 1e-6;
  t.rows[0].measured["speed"] = 1.0;
  EXPECT_TRUE(startsWith(errorMessageOf<DataError>([&] { writeSteadyStateTable(t, yaml); }),
                         yaml + ": cannot write the steady-state table: unknown output 'speed'"));
  TimeSeries s;
  s.t = {0, 1, 2};
  s.position.assign(3, Vec3::Zero());
  s.omega_cmd = {1, 1};
  s.position_noise = 1e-3;
  EXPECT_TRUE(
      startsWith(errorMessageOf<DataError>([&] { writeTimeSeries(s, yaml); }),
                 yaml + ": cannot write the time series: omega_cmd has 2 samples, t has 3"));
}

// A file in a directory that does not exist: the message names the directory.
TEST(DataIo, WriterNamesAMissingDirectory) {
  TempDir dir;
  const std::string missing = (dir.path() / "not_made").string();
  const std::string yaml = missing + "/w.yaml";
  SteadyStateTable t = oneRowTable();
  t.noise["v"] = 1e-6;
  const std::string message = errorMessageOf<DataError>([&] { writeSteadyStateTable(t, yaml); });
  EXPECT_NE(message.find("its directory '" + missing + "' does not exist"), std::string::npos)
      << message;
}

// ------------------------------------------------------------------------------ malformed input
// Each case asserts the exact file:line:column prefix of the message.

TEST(DataIoErrors, MissingMetadataFile) {
  TempDir dir;
  const std::string yaml = (dir.path() / "nothere.yaml").string();
  EXPECT_TRUE(startsWith(readError(yaml), yaml + ": cannot open the metadata file"));
}

TEST(DataIoErrors, YamlSyntaxError) {
  TempDir dir;
  const std::string yaml =
      dir.write("t.yaml", "kind: steady_state\nnoise: {v_mm_s: 1\ncsv: t.csv\n");
  EXPECT_TRUE(startsWith(readError(yaml), yaml + ":3:4: YAML syntax error"));
}

TEST(DataIoErrors, DuplicateMetadataKeyIsNotIgnored) {
  // yaml-cpp answers a lookup with the first of two equal keys: the second (here a NaN noise)
  // would be dropped without a word.
  TempDir dir;
  dir.write("t.csv", "omega_T_rpm,v_mm_s\n60,1\n");
  const std::string yaml = dir.write(
      "t.yaml", "kind: steady_state\ncsv: t.csv\nnoise: {v_mm_s: 0.1}\nnoise: {v_mm_s: .nan}\n");
  EXPECT_TRUE(startsWith(readError(yaml), yaml + ":4:1: duplicate key 'noise'")) << readError(yaml);
}

TEST(DataIoErrors, UnknownMetadataKey) {
  TempDir dir;
  dir.write("t.csv", "omega_T_rpm,v_mm_s\n60,1\n");
  const std::string yaml =
      dir.write("t.yaml", "kind: steady_state\ncsv: t.csv\nsettle: 5\nnoise: {v_mm_s: 1}\n");
  const std::string message = readError(yaml);
  EXPECT_TRUE(startsWith(message, yaml + ":3:1: unknown key 'settle' (allowed: "));
  EXPECT_NE(message.find("settle_time_s"), std::string::npos) << message;
}

TEST(DataIoErrors, UnknownNoiseKey) {
  TempDir dir;
  dir.write("t.csv", "omega_T_rpm,v_mm_s\n60,1\n");
  const std::string yaml =
      dir.write("t.yaml", "kind: steady_state\ncsv: t.csv\nnoise:\n  v_mm_s: 1\n  v: 2\n");
  EXPECT_TRUE(startsWith(readError(yaml), yaml + ":5:3: unknown key 'noise.v'"));
}

TEST(DataIoErrors, WrongKind) {
  TempDir dir;
  const std::string yaml = dir.write("t.yaml", "csv: t.csv\nkind:   steady\n");
  EXPECT_TRUE(startsWith(readError(yaml),
                         yaml + ":2:9: kind: expected steady_state or time_series, got 'steady'"));
  const std::string none = dir.write("n.yaml", "csv: t.csv\n");
  EXPECT_TRUE(startsWith(readError(none), none + ":1:1: missing required key 'kind'"));
}

TEST(DataIoErrors, NonPositiveNoise) {
  TempDir dir;
  dir.write("t.csv", "omega_T_rpm,v_mm_s\n60,1\n");
  const std::string yaml =
      dir.write("t.yaml", "kind: steady_state\ncsv: t.csv\nnoise:\n  v_mm_s:   -1\n");
  EXPECT_EQ(readError(yaml), yaml + ":4:13: noise.v_mm_s must be > 0, got -1");
}

TEST(DataIoErrors, NonPositiveWindowAndNonNumericSettleTime) {
  TempDir dir;
  dir.write("t.csv", "omega_T_rpm,v_mm_s\n60,1\n");
  const std::string window =
      dir.write("w.yaml", "kind: steady_state\ncsv: t.csv\nwindow_s: 0\nnoise: {v_mm_s: 1}\n");
  EXPECT_EQ(readError(window), window + ":3:11: window_s must be in (0, 1000000] s, got 0");
  const std::string settle = dir.write(
      "s.yaml", "kind: steady_state\ncsv: t.csv\nsettle_time_s: ten\nnoise: {v_mm_s: 1}\n");
  EXPECT_EQ(readError(settle), settle + ":3:16: settle_time_s: expected a number, got 'ten'");
}

TEST(DataIoErrors, MissingCsvFile) {
  TempDir dir;
  const std::string yaml = dir.write("t.yaml", kTableYaml);
  EXPECT_TRUE(startsWith(readError(yaml),
                         yaml + ":2:6: csv: cannot open '" + (dir.path() / "t.csv").string()));
}

TEST(DataIoErrors, MissingRequiredColumn) {
  TempDir dir;
  const std::string csv = dir.write("t.csv", "# comment\nid,v_mm_s\nx,1\n");
  const std::string yaml = dir.write("t.yaml", kTableYaml);
  EXPECT_TRUE(startsWith(readError(yaml), csv + ":2:1: missing required column 'omega_T_rpm'"));
  const std::string series_csv = dir.write("s.csv", "t_s,x_mm,omega_T_rpm\n0,0,0\n");
  const std::string series = dir.write("s.yaml", kSeriesYaml);
  EXPECT_TRUE(startsWith(readError(series), series_csv + ":1:1: missing required column 'y_mm'"));
}

TEST(DataIoErrors, UnknownColumn) {
  TempDir dir;
  const std::string csv = dir.write("t.csv", "omega_T_rpm, v_mm_s, speed\n60,1,2\n");
  const std::string yaml = dir.write("t.yaml", kTableYaml);
  const std::string message = readError(yaml);
  EXPECT_TRUE(startsWith(message, csv + ":1:3: unknown column 'speed' (allowed: id, time_s, "
                                        "omega_T_rpm, v_mm_s, omega_h_rpm"));
  EXPECT_NE(message.find("section.field"), std::string::npos) << message;
}

TEST(DataIoErrors, OverrideColumnWithUnknownSection) {
  TempDir dir;
  const std::string csv = dir.write("t.csv", "omega_T_rpm,v_mm_s,robot.n_tails,tank.depth\n");
  const std::string yaml = dir.write("t.yaml", kTableYaml);
  EXPECT_TRUE(startsWith(readError(yaml),
                         csv + ":1:4: override column 'tank.depth' addresses an unknown config "
                               "section 'tank'"));
}

TEST(DataIoErrors, OverrideKeyInMetadataWithoutSection) {
  TempDir dir;
  dir.write("t.csv", "omega_T_rpm,v_mm_s\n60,1\n");
  const std::string yaml = dir.write(
      "t.yaml", "kind: steady_state\ncsv: t.csv\noverrides:\n  n_tails: 3\nnoise: {v_mm_s: 1}\n");
  EXPECT_TRUE(
      startsWith(readError(yaml), yaml + ":4:3: override 'n_tails' must look like section.field"));
}

TEST(DataIoErrors, DuplicateColumn) {
  TempDir dir;
  const std::string csv = dir.write("t.csv", "omega_T_rpm,v_mm_s,omega_h_rpm,v_mm_s\n60,1,2,3\n");
  const std::string yaml = dir.write("t.yaml", kTableYaml);
  EXPECT_EQ(readError(yaml), csv + ":1:4: duplicate column 'v_mm_s' (also column 2)");
}

TEST(DataIoErrors, WrongNumberOfFields) {
  TempDir dir;
  const std::string csv =
      dir.write("t.csv", "omega_T_rpm,v_mm_s,omega_h_rpm\n60,1,2\n\n# c\n60,1,2,4\n");
  const std::string yaml = dir.write("t.yaml", kTableYaml);
  EXPECT_EQ(readError(yaml), csv + ":5:4: expected 3 fields as in the header (line 1), got 4");
  dir.write("t.csv", "omega_T_rpm,v_mm_s,omega_h_rpm\n60,1\n");
  EXPECT_EQ(readError(yaml), csv + ":2:3: expected 3 fields as in the header (line 1), got 2");
}

TEST(DataIoErrors, NonNumericCell) {
  TempDir dir;
  const std::string csv = dir.write("t.csv",
                                    "id,omega_T_rpm,omega_h_rpm,v_mm_s\n"
                                    "a,60,1,2\n"
                                    "b,60,1,2\n"
                                    "c,60,1,2\n"
                                    "d,60,1,2\n"
                                    "#\n"
                                    "e,60,abc,2\n");
  const std::string yaml = dir.write("t.yaml", kTableYaml);
  EXPECT_EQ(readError(yaml), csv + ":7:3: column 'omega_h_rpm': expected a number, got 'abc'");
}

TEST(DataIoErrors, NonFiniteCell) {
  TempDir dir;
  const std::string csv = dir.write("s.csv",
                                    "t_s,x_mm,y_mm,omega_T_rpm\n"
                                    "0,0,0,1\n"
                                    "1,inf,0,1\n");
  const std::string yaml = dir.write("s.yaml", kSeriesYaml);
  EXPECT_EQ(readError(yaml), csv + ":3:2: column 'x_mm': expected a finite number, got 'inf'");
  dir.write("s.csv", "t_s,x_mm,y_mm,omega_T_rpm\n0,0,0,1\n1,0,1e999,1\n");
  EXPECT_EQ(readError(yaml), csv + ":3:3: column 'y_mm': expected a finite number, got '1e999'");
}

TEST(DataIoErrors, EmptyRequiredCell) {
  TempDir dir;
  const std::string csv = dir.write("t.csv", "omega_T_rpm,v_mm_s\n60,1\n ,2\n");
  const std::string yaml = dir.write("t.yaml", kTableYaml);
  EXPECT_EQ(readError(yaml), csv +
                                 ":3:1: column 'omega_T_rpm': expected a number, got an "
                                 "empty cell");
}

TEST(DataIoErrors, TimeNotStrictlyIncreasing) {
  TempDir dir;
  const std::string csv = dir.write("s.csv",
                                    "omega_T_rpm,t_s,x_mm,y_mm\n"
                                    "1,0,0,0\n"
                                    "1,0.5,0,0\n"
                                    "1,0.5,0,0\n");
  const std::string yaml = dir.write("s.yaml", kSeriesYaml);
  EXPECT_EQ(readError(yaml),
            csv + ":4:2: column 't_s': time must be strictly increasing, got 0.5 after 0.5");
}

TEST(DataIoErrors, ZeroNormQuaternion) {
  TempDir dir;
  const std::string csv = dir.write("s.csv",
                                    "t_s,x_mm,y_mm,omega_T_rpm,qx,qy,qz,qw\n"
                                    "0,0,0,1,0,0,0,1\n"
                                    "1,0,0,1,0,0,0,0\n"
                                    "2,0,0,1,0,0,0,1\n");
  const std::string yaml = dir.write("s.yaml", kSeriesYaml);
  EXPECT_TRUE(startsWith(readError(yaml), csv + ":3:8: quaternion (qw, qx, qy, qz) has norm 0;"));
}

TEST(DataIoErrors, IncompleteQuaternionGroup) {
  TempDir dir;
  const std::string csv = dir.write("s.csv", "t_s,x_mm,y_mm,omega_T_rpm,qx,qw,qz\n");
  const std::string yaml = dir.write("s.yaml", kSeriesYaml);
  EXPECT_TRUE(startsWith(readError(yaml), csv + ":1:5: the quaternion columns come as a group of "
                                                "four (qw, qx, qy, qz); missing qy"));
}

TEST(DataIoErrors, TooFewSamples) {
  TempDir dir;
  const std::string csv =
      dir.write("s.csv", "t_s,x_mm,y_mm,omega_T_rpm\n0,0,0,1\n1,0,0,1\n# end\n");
  const std::string yaml = dir.write("s.yaml", kSeriesYaml);
  EXPECT_EQ(readError(yaml), csv + ":3:1: a time series needs at least 3 data rows, got 2");
}

TEST(DataIoErrors, NoiseMissingForMeasuredColumn) {
  TempDir dir;
  dir.write("t.csv", "omega_T_rpm,v_mm_s,omega_t_rpm\n60,1,2\n");
  const std::string yaml = dir.write("t.yaml", kTableYaml);
  EXPECT_TRUE(startsWith(readError(yaml), yaml + ":3:1: noise.omega_t_rpm is required"));
  const std::string bare = dir.write("b.yaml", "kind: steady_state\ncsv: t.csv\n");
  EXPECT_TRUE(startsWith(readError(bare), bare + ":1:1: noise.v_mm_s is required"));
}

TEST(DataIoErrors, NoiseMissingForOrientationAndTurns) {
  TempDir dir;
  dir.write("s.csv",
            "t_s,x_mm,y_mm,omega_T_rpm,qw,qx,qy,qz,tail_turns\n"
            "0,0,0,1,1,0,0,0,0\n1,0,0,1,1,0,0,0,0\n2,0,0,1,1,0,0,0,0\n");
  const std::string q = dir.write("q.yaml",
                                  "kind: time_series\ncsv: s.csv\nnoise:\n  position_mm: 1\n"
                                  "  turns: 1\n");
  EXPECT_TRUE(startsWith(readError(q), q + ":3:1: noise.orientation_rad is required"));
  const std::string turns = dir.write(
      "t.yaml", "kind: time_series\ncsv: s.csv\nnoise: {position_mm: 1, orientation_rad: 1}\n");
  EXPECT_TRUE(startsWith(readError(turns), turns + ":3:1: noise.turns is required"));
  const std::string pos =
      dir.write("p.yaml", "kind: time_series\ncsv: s.csv\nnoise: {orientation_rad: 1, turns: 1}\n");
  EXPECT_TRUE(startsWith(readError(pos), pos + ":3:1: noise.position_mm is required"));
}

TEST(DataIoErrors, CsvAndBagTogetherOrBagOptionsWithCsv) {
  TempDir dir;
  dir.write("s.csv", "t_s,x_mm,y_mm,omega_T_rpm\n0,0,0,1\n1,0,0,1\n2,0,0,1\n");
  const std::string both =
      dir.write("b.yaml", "kind: time_series\ncsv: s.csv\nbag: s.bag\nnoise: {position_mm: 1}\n");
  EXPECT_EQ(readError(both), both + ":3:1: give either csv or bag, not both");
  const std::string option = dir.write(
      "o.yaml",
      "kind: time_series\ncsv: s.csv\nnoise: {position_mm: 1}\nbag_position: camera_fix\n");
  EXPECT_EQ(readError(option), option + ":4:1: bag_position applies only to bag input (bag:)");
  const std::string neither = dir.write("n.yaml", "kind: time_series\nnoise: {position_mm: 1}\n");
  EXPECT_TRUE(
      startsWith(readError(neither), neither + ":1:1: missing required key 'csv' or 'bag'"));
}

TEST(DataIoErrors, UnterminatedQuote) {
  TempDir dir;
  const std::string csv = dir.write("t.csv", "id,omega_T_rpm,v_mm_s\n\"abc,60,1\n");
  const std::string yaml = dir.write("t.yaml", kTableYaml);
  EXPECT_TRUE(startsWith(readError(yaml), csv + ":2:1: unterminated quote"));
}

TEST(DataIoErrors, EmptyFiles) {
  TempDir dir;
  const std::string csv = dir.write("t.csv", "# only a comment\n\n");
  const std::string yaml = dir.write("t.yaml", kTableYaml);
  EXPECT_TRUE(startsWith(readError(yaml), csv + ": no header line"));
  const std::string empty = dir.write("e.yaml", "");
  EXPECT_TRUE(startsWith(readError(empty), empty + ": the metadata file is empty"));
  const std::string list = dir.write("l.yaml", "- kind\n- csv\n");
  EXPECT_TRUE(startsWith(readError(list), list + ":1:1: expected a map of metadata fields"));
}

TEST(DataIoErrors, NoMeasuredColumnOrNoRows) {
  TempDir dir;
  const std::string csv = dir.write("t.csv", "id,omega_T_rpm\nx,60\n");
  const std::string yaml = dir.write("t.yaml", kTableYaml);
  EXPECT_TRUE(startsWith(readError(yaml), csv + ":1:1: no measured column"));
  dir.write("t.csv", "# c\nomega_T_rpm,v_mm_s\n");
  EXPECT_EQ(readError(yaml), csv + ":2:1: no data rows after the header");
}

// Values no measurement can take (issue: accepted, then Newton failed 16 s into the fit).
TEST(DataIoErrors, ImplausibleTableValues) {
  TempDir dir;
  const std::string csv = dir.write("t.csv", "omega_T_rpm,v_mm_s,omega_h_rpm\n60,1e308,2\n");
  const std::string yaml = dir.write("t.yaml", kTableYaml);
  EXPECT_EQ(readError(yaml), csv +
                                 ":2:2: column 'v_mm_s': 1e+308 mm/s is outside the plausible "
                                 "range [-10000, 10000] mm/s");
  dir.write("t.csv", "omega_T_rpm,v_mm_s,omega_h_rpm\n-1e308,1,2\n");
  EXPECT_TRUE(startsWith(readError(yaml), csv + ":2:1: column 'omega_T_rpm': -1e+308 rpm is "
                                                "outside the plausible range"));
  dir.write("t.csv", "time_s,omega_T_rpm,v_mm_s\n-5,60,1\n");
  EXPECT_TRUE(startsWith(readError(yaml), csv + ":2:1: column 'time_s': -5 s is outside"));
  // The ends of the ranges are accepted.
  dir.write("t.csv", "time_s,omega_T_rpm,v_mm_s\n0,10000,-10000\n");
  EXPECT_NO_THROW(readMeasuredData(yaml));
}

TEST(DataIoErrors, ImplausibleSeriesValues) {
  TempDir dir;
  const std::string yaml = dir.write("s.yaml", kSeriesYaml);
  const std::string csv =
      dir.write("s.csv", "t_s,x_mm,y_mm,omega_T_rpm\n-1,0,0,1\n0,0,0,1\n1,0,0,1\n");
  EXPECT_EQ(readError(yaml),
            csv + ":2:1: column 't_s': -1 s is outside the plausible range [0, 1000000] s");
  dir.write("s.csv", "t_s,x_mm,y_mm,omega_T_rpm\n0,0,0,1\n1,-1e308,0,1\n2,0,0,1\n");
  EXPECT_TRUE(startsWith(readError(yaml), csv + ":3:2: column 'x_mm': -1e+308 mm is outside"));
  dir.write("s.csv", "t_s,x_mm,y_mm,omega_T_rpm,tail_turns\n0,0,0,1,0\n1,0,0,1,2e9\n2,0,0,1,0\n");
  EXPECT_TRUE(startsWith(readError(yaml), csv + ":3:5: column 'tail_turns': 2000000000 turns"));
  const std::string late =
      dir.write("l.yaml", std::string(kSeriesYaml) + "session_time_s: 1e308\n");
  dir.write("s.csv", "t_s,x_mm,y_mm,omega_T_rpm\n0,0,0,1\n1,0,0,1\n2,0,0,1\n");
  EXPECT_EQ(readError(late), late + ":7:17: session_time_s must be in [0, 1000000] s, got 1e+308");
}

TEST(DataIoErrors, NonUnitQuaternion) {
  TempDir dir;
  const std::string yaml = dir.write("s.yaml", kSeriesYaml);
  const std::string csv = dir.write("s.csv",
                                    "t_s,x_mm,y_mm,omega_T_rpm,qw,qx,qy,qz\n"
                                    "0,0,0,1,1,0,0,0\n"
                                    "1,0,0,1,2,0,0,0\n"
                                    "2,0,0,1,1,0,0,0\n");
  EXPECT_EQ(readError(yaml), csv +
                                 ":3:5: quaternion (qw, qx, qy, qz) has norm 2; expected a unit "
                                 "quaternion (norm within 0.001 of 1)");
  // Rounding of a unit quaternion to four decimals is within the tolerance, and normalised.
  dir.write("s.csv",
            "t_s,x_mm,y_mm,omega_T_rpm,qw,qx,qy,qz\n"
            "0,0,0,1,0.7071,0.7071,0,0\n1,0,0,1,1,0,0,0\n2,0,0,1,1,0,0,0\n");
  const MeasuredData data = readMeasuredData(yaml);
  EXPECT_NEAR(data.series.at(0).orientation.at(0).norm(), 1.0, 1e-12);
}

}  // namespace
}  // namespace flagella::identify
