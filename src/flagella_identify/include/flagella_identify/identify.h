// The whole discovery pipeline: calibrate the baseline on the training split, diagnose the
// held-out residual, fit every identifiable candidate effect together with the baseline
// parameters, select by held-out error with a parsimony penalty and a significance test
// against the measurement noise, and name a cause only with that evidence.
#pragma once

#include <yaml-cpp/yaml.h>

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "flagella_identify/chi_square.h"
#include "flagella_identify/cross_validation.h"
#include "flagella_identify/diagnosis.h"
#include "flagella_identify/fit.h"
#include "flagella_identify/power_check.h"

namespace flagella {
namespace identify {

struct IdentifyOptions {
  std::vector<std::string> free;        ///< baseline config paths to fit
  std::vector<std::string> candidates;  ///< candidate names; empty = the standard list
  int max_effects = 2;                  ///< largest number of effects named together
  /// The methods of docs/model.md 7.6, each on by default (off: the pipeline without it, for
  /// before/after comparisons): cross validation of small tables, the power check ("cannot
  /// tell"), continuation fits of a baseline off its map.
  bool cross_validation = true;
  bool power_check = true;
  bool continuation = true;
  EvaluatorOptions evaluator;
  FitOptions fit;
  /// Caps the iterations of the single candidates' first fits: 0 (no cap: fit.max_iterations)
  /// or 1 to fit.max_iterations; anything else is refused (ConfigError naming the field). A
  /// diagnostic: it shows what the pair rule (docs/model.md 7.6) does with a single fit that
  /// stopped short of its optimum; the rule's own refits are never capped.
  int single_fit_max_iterations = 0;
  /// The pair rule itself (off: the pipeline without it, for before/after comparisons).
  bool pair_rule = true;
  /// docs/model.md 7.6: the candidates' fits (each alone, by continuation, paired with the best)
  /// two at a time when evaluator.jobs >= 2 and not under mpirun, their model runs sharing the
  /// jobs; progress is printed in the sequential order, and every fit and verdict is the same as
  /// one at a time (false).
  bool concurrent_fits = true;
  std::function<void(const std::string&)> progress;
};

/// One fitted model (the baseline, one candidate, or a pair) judged on the held-out data.
struct ModelOutcome {
  std::string label;                 ///< "baseline", "granular_yield", "dc_motor + com_offset"
  std::vector<std::string> effects;  ///< candidate names in the model
  bool fitted = false;
  /// Never fitted because the candidate cannot act on this robot or be seen in these data
  /// (Identification::skipReason, given in `note`).
  bool skipped = false;
  std::string note;  ///< why it was not fitted, or how the fit ended
  /// Parameters that ended off their map (fit.h offTheMap), after the continuation fit if
  /// one was tried; reported, never silently accepted.
  std::vector<std::string> warnings;
  bool continuation = false;  ///< the fit went through the series' summary features first
  std::vector<FitParameter> parameters;
  int extra_parameters = 0;  ///< parameters beyond the baseline's
  double train_chi_square = 0.0;
  int train_count = 0;
  double held_out_chi_square = 0.0;
  int held_out_count = 0;
  double held_out_rms_z = 0.0;
  double noise_z = 0.0;  ///< significance of the remaining held-out residual
  /// Share of the calibrated baseline's held-out excess over the noise (chi^2 - N) removed.
  double explained = 0.0;
  double improvement = 0.0;  ///< held-out chi^2 drop against the reference model
  double penalty = 0.0;      ///< parsimony: extra parameters x ln(held-out count)
  double critical = 0.0;     ///< chi-square critical value (p = 1e-3) for the extras
  bool significant = false;  ///< improvement - penalty > critical
  int evaluations = 0;
  /// How the last fit ended (docs/model.md 7.6: no verdict on a fit short of its optimum):
  /// iterations, whether it met its convergence test, the largest gradient component.
  int iterations = 0;
  bool converged = false;
  double gradient_max_norm = std::numeric_limits<double>::quiet_NaN();
  /// The starts the fit was run from, one line each ("best of 5 starts for dc_motor ..."); with
  /// several, how each ended and which was kept.
  std::vector<std::string> starts;
  Evaluation held_out;  ///< the fitted model's held-out residuals
};

/// kCannotTell: the baseline fits, but these data could not have shown a candidate effect of
/// realistic strength (power_check.h); or the baseline misses them and two candidates (or
/// pairs) explain them equally well (closestRival). The report says which measurement would
/// decide.
enum class Verdict { kNoDiscrepancy, kNamedCause, kUnexplained, kCannotTell };
std::string verdictText(Verdict v);

struct IdentifyResult {
  Verdict verdict = Verdict::kNoDiscrepancy;
  std::vector<std::string> named;  ///< the named causes (empty unless kNamedCause)
  std::string summary;             ///< one paragraph: the decision and the evidence
  ModelOutcome baseline;
  Diagnosis baseline_diagnosis;            ///< calibrated baseline on the held-out data
  std::vector<ModelOutcome> candidates;    ///< single candidates, fitted or skipped
  std::vector<ModelOutcome> combinations;  ///< pairs tried when one effect was not enough
  std::optional<ModelOutcome> chosen;      ///< the extended model (named or best partial)
  Diagnosis chosen_diagnosis;
  double gain = 0.0;  ///< 1 - held-out RMS z after / before (0 when nothing is named)
  int total_evaluations = 0;
  /// The most candidate fits that ran at once (IdentifyOptions::concurrent_fits): 1 or 2.
  int fits_at_once = 1;
  /// How the models were judged: "held-out split (...)" or "k-fold cross validation (...)";
  /// with cross validation every held-out figure above is cross-validated.
  std::string validation;
  std::vector<std::string> validation_notes;  ///< rows that always train, and why
  /// Whether these data could have shown each steady-state candidate at its weakest realistic
  /// strength (run when the baseline shows no discrepancy in tables), and the measurements
  /// that would separate the ones they could not.
  std::vector<PowerCheck> power;
  std::vector<SuggestedMeasurement> suggestions;
  /// The pair rule (docs/model.md 7.6): before a pair is named each of its effects is fitted
  /// again alone (Identification::refitAlone); what that gave, in words (empty when no pair was
  /// chosen), and those refits.
  std::string pair_check;
  std::vector<ModelOutcome> pair_refits;
};

/// The pipeline; its parts live in src/: identify.cpp (run, in order), training_fits.cpp,
/// start_values.cpp, held_out_judgement.cpp, identification_folds.cpp, candidate_search.cpp,
/// pair_rule.cpp, cannot_tell.cpp and verdict_text.cpp.
class Identification {
 public:
  Identification(MeasuredData data, YAML::Node baseline, std::string baseline_source,
                 IdentifyOptions options);
  IdentifyResult run();

  const Evaluator& evaluator() const { return evaluator_; }
  /// The rows the verdict was judged on: the split's held-out rows, or with cross validation
  /// the rows held out in some fold.
  Split heldOutRows() const;
  /// The model of an outcome (baseline or extended) with its fitted values.
  Model modelOf(const ModelOutcome& outcome) const;

 private:
  /// Why candidate `c` is not tried ("" if it is): it cannot act on the baseline robot, or the
  /// data lack what would show it (the note says which).
  std::string skipReason(const Candidate& c, unsigned observables) const;
  ModelOutcome fitModelOutcome(const std::vector<const Candidate*>& effects,
                               const ModelOutcome& reference);
  /// The fit on the training data (every row with cross validation), not yet judged. With time
  /// series, a baseline fit that ends off its map is tried again by continuation (summary
  /// features first, then the samples) and the better one kept (candidates: fitCandidates).
  ModelOutcome fitOnTraining(const std::vector<const Candidate*>& effects,
                             const ModelOutcome& reference);
  /// The fit through the series' summary features first, then the samples.
  ModelOutcome fitByContinuation(const std::vector<const Candidate*>& effects,
                                 const ModelOutcome& reference);
  /// The one of lower training chi^2 (the continuation's only if it is fitted), with both
  /// fits' evaluations.
  ModelOutcome betterOf(ModelOutcome direct, ModelOutcome continued) const;
  /// One fit from the best start; with `features`, fitted on them first, then on the samples.
  ModelOutcome fitFrom(const std::vector<const Candidate*>& effects, const ModelOutcome& reference,
                       const Evaluator* features);
  /// The held-out residuals of a fitted outcome (each fold's refit with cross validation) and
  /// the scores against `reference`; unfitted when they cannot be simulated.
  void judge(ModelOutcome& out, const ModelOutcome& reference);
  /// The scores of `out` (held-out residuals already in it) against `reference`: noise test,
  /// share explained and whether it is significant over `reference` (judge's test).
  void scoreAgainst(ModelOutcome& out, const ModelOutcome& reference) const;
  Evaluation crossValidatedResiduals(const ModelOutcome& out, int& evaluations) const;
  /// The folds, from each row's information about the calibrated baseline's parameters.
  void planCrossValidation(const ModelOutcome& baseline, IdentifyResult& result);
  /// The power of the data against each steady-state candidate; the verdict "cannot tell"
  /// when one of realistic strength would not have shown but a measurement would show it.
  bool cannotTell(IdentifyResult& result);
  /// The verdict "cannot tell between" the chosen model and `rival`, with the steady
  /// measurements that separate them.
  void cannotTellBetween(IdentifyResult& result, const ModelOutcome& rival);
  /// Fits every identifiable candidate (of the options' list) alone with the baseline;
  /// records skipped ones with the reason.
  void fitCandidates(IdentifyResult& result);
  /// When the best single effect `chosen` leaves a significant residual and explains enough to
  /// mask a second effect, fits it paired with each other fitted candidate (into
  /// result.combinations) and replaces `chosen` by the best significant pair.
  void tryPairs(IdentifyResult& result, std::optional<ModelOutcome>& chosen);
  /// The pair rule: the pair `chosen` is kept only if it is still significant over the better
  /// of its two effects, each fitted again alone (refitAlone); otherwise the refits replace the
  /// single fits they improve and the best significant single effect is chosen. Says which in
  /// result.pair_check, and keeps the refits in result.pair_refits.
  void checkPairAgainstItsSingles(IdentifyResult& result, std::optional<ModelOutcome>& chosen);
  /// Effect `member` (0 or 1) of `pair` alone, never capped: fitted from the pair's optimum
  /// with the other effect off, against its own first fit if that converged, else fitted again
  /// from that fit's end (from its start points if it failed); the one of lower training chi^2,
  /// judged against the baseline, each start's ending in its `starts`.
  ModelOutcome refitAlone(const IdentifyResult& result, const ModelOutcome& pair, size_t member);
  /// With cross validation: the fewest rows any fold trains on.
  int fewestTrainingRows() const;
  void say(const std::string& line) const;
  /// A progress line of say() (from_fit false) or of a fit (options_.fit.progress): held while
  /// this thread runs one of several concurrent fits, else printed.
  void emit(bool from_fit, const std::string& line) const;
  /// options_.fit.progress, held like say() while fits run concurrently (null if unset).
  std::function<void(const std::string&)> fitProgress() const;
  /// How many of `count` independent fits run at once (IdentifyOptions::concurrent_fits).
  int fitsAtOnce(int count) const;
  /// Runs each fit (it stores its own outcome), fitsAtOnce at a time; every fit's progress
  /// lines are printed in `fits` order after all have ended.
  void runFits(const std::vector<std::function<void()>>& fits);

  MeasuredData data_;
  YAML::Node baseline_;
  std::string source_;
  IdentifyOptions options_;
  Evaluator evaluator_;
  std::optional<CrossValidationPlan> folds_;  ///< set when the data are cross-validated
  double baseline_excess_ = 0.0;              ///< held-out chi^2 - N of the calibrated baseline
  bool capping_singles_ = false;  ///< single_fit_max_iterations applies (fitCandidates only)
  int most_fits_at_once_ = 1;     ///< IdentifyResult::fits_at_once so far
};

/// A model explains the discrepancy when it removes at least this share of the baseline's
/// held-out excess chi^2 (a cause is named only then).
constexpr double kExplainedShare = 0.9;

/// A second effect is tried with the best single one only when that one removes at least this
/// share of the baseline's held-out excess (a weaker first effect cannot mask a second one).
constexpr double kPairingShare = 0.25;

/// The model the data cannot tell from `chosen` (docs/model.md 7.6): another fitted,
/// significant outcome of as many effects (result.candidates or result.combinations) that
/// explains the discrepancy too (kExplainedShare) and whose selection score (held-out chi^2 +
/// parsimony penalty) exceeds the chosen one's by less than chiSquareCritical(1); the closest
/// such, or nullptr.
const ModelOutcome* closestRival(const IdentifyResult& result, const ModelOutcome& chosen);

}  // namespace identify
}  // namespace flagella
