// Phase-free summary features of a time series (docs/model.md 7.6), the first stage of a
// continuation fit: per stretch of constant motor command, the mean horizontal speed over 5 s
// windows, the yaw rate (slope of the heading of the head axis, else of the window
// displacements), and the head and tail turn rates. Unlike positions, they do not wrap when a
// model circles at another rate, so a fit on them does not run to its bounds.
#pragma once

#include "flagella_identify/residuals.h"

namespace flagella {
namespace identify {

/// Window of the speed feature [s].
constexpr double kFeatureWindow = 5.0;
/// Each stretch of constant command loses this share at its start (the transient) ...
constexpr double kFeatureSettleShare = 0.25;
/// ... and gives features only if at least this long remains [s].
constexpr double kFeatureMinStretch = 15.0;

/// Appends the feature residuals (outputs "speed", "yaw_rate", "head_rate", "tail_rate") of
/// the samples of `s` (index `source`) in [t0, t1) against the simulated `trace`, whose
/// horizontal plane is normal to `up`.
void appendFeatureResiduals(const TimeSeries& s, int source, double t0, double t1,
                            const SeriesTrace& trace, const Vec3& up, Evaluation& out);

}  // namespace identify
}  // namespace flagella
