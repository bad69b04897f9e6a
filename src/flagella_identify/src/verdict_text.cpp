// The verdict in words: the summary of each decision and its cautions (docs/model.md 7.6).
#include "identify_internal.h"
#include "text_format.h"

namespace flagella {
namespace identify {

std::string verdictText(Verdict v) {
  switch (v) {
    case Verdict::kNoDiscrepancy:
      return "no significant discrepancy";
    case Verdict::kNamedCause:
      return "named cause";
    case Verdict::kUnexplained:
      return "unexplained residual";
    case Verdict::kCannotTell:
      return "cannot tell from these data";
  }
  return "?";
}

std::string noDiscrepancySummary(const Diagnosis& d) {
  return formatted(
      "No significant discrepancy: the calibrated baseline predicts the held-out data within "
      "the measurement noise (RMS z %.2f over %.0f residuals, noise test z = %.2f < %.1f). No "
      "effect is named.",
      d.rms_z, d.count, d.noise_z, kSignificanceZ);
}

namespace {

/// "kind in output; ..." of the diagnosis' signatures, or "no simple signature".
std::string signatureList(const Diagnosis& d) {
  std::string signatures;
  for (const Signature& s : d.signatures)
    signatures += (signatures.empty() ? "" : "; ") + s.kind + " in " + s.output;
  if (signatures.empty()) signatures = "no simple signature";
  return signatures;
}

}  // namespace

void decideVerdict(IdentifyResult& result, const std::optional<ModelOutcome>& chosen) {
  const Diagnosis& d = result.baseline_diagnosis;
  const std::string signatures = signatureList(d);
  if (chosen && chosen->explained >= kExplainedShare) {
    result.verdict = Verdict::kNamedCause;
    result.named = chosen->effects;
    result.summary = "Named cause: " + joined(chosen->effects, " + ") +
                     formatted(
                         ". The calibrated baseline misses the held-out data (RMS z %.2f, noise "
                         "test z = %.1f; ",
                         d.rms_z, d.noise_z);
    result.summary += signatures +
                      formatted(
                          "). With the effect the held-out RMS z is %.2f (noise test "
                          "z = %.2f); it removes %.1f %% of the baseline's excess "
                          "over the noise",
                          chosen->held_out_rms_z, chosen->noise_z, 100.0 * chosen->explained) +
                      formatted("; the held-out chi^2 drops by %.1f", chosen->improvement) +
                      formatted(
                          ", more than the parsimony penalty %.1f plus the p = 0.001 critical "
                          "value %.1f. Held-out gain %.0f %%.",
                          chosen->penalty, chosen->critical, 100.0 * result.gain);
  } else {
    result.verdict = Verdict::kUnexplained;
    result.summary = formatted(
                         "Unexplained residual: the calibrated baseline misses the held-out data "
                         "(RMS z %.2f, noise test z = %.1f) with signature: ",
                         d.rms_z, d.noise_z) +
                     signatures + ". ";
    if (chosen)
      result.summary +=
          formatted("The best candidate model (" + chosen->label +
                        ") reduces the held-out RMS z to %.2f but removes only %.0f %% of "
                        "the excess over the noise (noise test z = %.1f), so no cause is "
                        "named.",
                    chosen->held_out_rms_z, 100.0 * chosen->explained, chosen->noise_z);
    else
      result.summary +=
          "No candidate effect improves the held-out error significantly, so no "
          "cause is named.";
  }
}

void cautionOffTheMap(IdentifyResult& result) {
  const ModelOutcome& b = result.baseline;
  if (b.warnings.empty()) return;
  result.summary +=
      " Caution: the calibrated baseline ended off its map (" + joined(b.warnings, "; ") + ")" +
      (b.continuation ? ", also when fitted through the series' summary features first" : "") +
      ": its figures are those of a model at the edge of its range, not a "
      "calibration of the robot.";
}

}  // namespace identify
}  // namespace flagella
