// Small rod networks and helpers shared by the unit tests.
#pragma once

#include <random>

#include "flagella_sim/rod/network_builder.h"

namespace flagella::testing {

/// Tail-like material of the granular robots (docs/model.md 8.1): VPS, r0 = 3.2 mm.
RodMaterial vpsMaterial();

/// Straight rod along +z from the origin, `edges` equal edges over `length`.
RodNetwork makeStraightRod(int edges, double length, const RodMaterial& material);

/// A curved, twisted junction network: a central node with three edges leaving it (two of
/// them need flipping at the junction) plus short chains, so springs with every sign
/// combination exist. Rest shape is bent, so natural curvatures are non-zero.
RodNetwork makeJunctionNetwork(const RodMaterial& material);

/// A lone rigid head: nodes x_0, x_1, x_2 on the z axis at -half_length, 0, +half_length, two
/// stiff edges (head edge e_0, shaft edge e_1) and a stiff spring between them; no tails and no
/// motor spring, so loads on the head alone can be checked against closed forms.
RodNetwork makeLoneHead(double half_length, const RodMaterial& material);

/// A small three-tail robot (docs/model.md 8.1 layout): tails of 5 cm with `tail_edges` edges
/// each, VPS material.
RodNetwork makeThreeTailRobot(int tail_edges);

/// q with every position moved by up to `amplitude` and every theta by up to `angle`.
VecX perturbed(const RodNetwork& net, const VecX& q, double amplitude, double angle,
               std::mt19937& rng);

}  // namespace flagella::testing
