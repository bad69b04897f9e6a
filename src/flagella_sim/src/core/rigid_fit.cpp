#include "flagella_sim/core/rigid_fit.h"

#include <Eigen/SVD>
#include <algorithm>
#include <stdexcept>

namespace flagella {

namespace {

Vec3 centroidOf(const std::vector<Vec3>& points) {
  Vec3 sum = Vec3::Zero();
  for (const Vec3& p : points) sum += p;
  return sum / static_cast<double>(points.size());
}

}  // namespace

RigidFit bestRigidFit(const std::vector<Vec3>& from, const std::vector<Vec3>& to) {
  if (from.size() != to.size() || from.empty())
    throw std::invalid_argument("bestRigidFit: point sets of sizes " + std::to_string(from.size()) +
                                " and " + std::to_string(to.size()));
  const Vec3 cy = centroidOf(from), cx = centroidOf(to);
  Mat3 covariance = Mat3::Zero();  // H = sum (y_i - cy)(x_i - cx)^T
  for (size_t i = 0; i < from.size(); ++i) covariance += (from[i] - cy) * (to[i] - cx).transpose();
  // Kabsch: H = U S V^T, R = V diag(1, 1, d) U^T with d = sign det(V U^T) (no reflection)
  const Eigen::JacobiSVD<Mat3> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 d = Mat3::Identity();
  d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  RigidFit fit;
  fit.rotation = svd.matrixV() * d * svd.matrixU().transpose();
  fit.translation = cx - fit.rotation * cy;
  for (size_t i = 0; i < from.size(); ++i)
    fit.deviation =
        std::max(fit.deviation, (to[i] - (fit.rotation * from[i] + fit.translation)).norm());
  return fit;
}

}  // namespace flagella
