// What a calibrated model gets wrong, in the terms of the data: which outputs, by how much,
// where (motor-speed range, sign of rotation, part of a run, session time) and the signature
// (bias, threshold, saturation, asymmetry, drift, oscillation, intermittency).
#pragma once

#include <string>
#include <vector>

#include "flagella_identify/evaluation.h"

namespace flagella {
namespace identify {

struct OutputStats {
  std::string output;
  std::string unit;  ///< unit of the *_error fields (display units: mm/s, rpm, mm, ...)
  int count = 0;
  double rms_z = 0.0;  ///< RMS of (model - data)/sigma
  double mean_z = 0.0;
  double rms_error = 0.0;  ///< RMS of model - data, display units
  double mean_error = 0.0;
  double noise_z = 0.0;  ///< significance of the excess over the noise (see noiseZScore)
};

struct GroupStats {
  std::string group;  ///< e.g. "|omega_T| 40-120 rpm", "omega_T > 0", "run 0-48 s"
  int count = 0;
  double rms_z = 0.0;
  double mean_z = 0.0;
};

struct Signature {
  std::string
      kind;  ///< bias | threshold | saturation | asymmetry | drift | oscillation | intermittency
  std::string output;      ///< the output it was found in
  double statistic = 0.0;  ///< its significance, in standard deviations
  std::string text;        ///< one sentence in the terms of the data
};

struct Diagnosis {
  int count = 0;
  double chi_square = 0.0;
  double rms_z = 0.0;
  double noise_z = 0.0;  ///< > kSignificanceZ: the residual is larger than the noise
  bool significant = false;
  std::vector<OutputStats> outputs;
  std::vector<GroupStats> where;
  std::vector<Signature> signatures;
};

/// Significance level (one-sided, in standard deviations) of every test in the tool.
constexpr double kSignificanceZ = 3.5;

/// z-score of a chi-square value with n degrees of freedom (Wilson-Hilferty): about N(0,1)
/// when the residuals are pure measurement noise.
double noiseZScore(double chi_square, int n);

Diagnosis diagnose(const Evaluation& evaluation, const MeasuredData& data);

/// Display unit and factor (SI -> display) of an output.
std::pair<std::string, double> displayUnit(const std::string& output);

}  // namespace identify
}  // namespace flagella
