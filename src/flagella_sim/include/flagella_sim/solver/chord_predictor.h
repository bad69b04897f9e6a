// The rotating predictor of a node's next step (docs/model.md 1.10): the chord (q_{k+1} - q_k)/dt
// extrapolated from the last two as a turn at the same rate, instead of linearly.
#pragma once

#include "flagella_sim/core/types.h"

namespace flagella {

/// The next chord velocity from the previous one `v_prev` and the last one `v_last`: `v_last`
/// turned by the rotation that took `v_prev` to it and scaled by |v_last| / |v_prev|, which is
/// exact for a point moving on a circle at a steady rate (or a steadily growing or shrinking
/// one). Falls back to the linear 2 v_last - v_prev when either chord is zero or they differ by
/// more than 60 deg (a turn that large per step is not a smooth rotation).
Vec3 rotatingChordPrediction(const Vec3& v_prev, const Vec3& v_last);

}  // namespace flagella
