// Basic linear-algebra aliases shared by the whole core library.
#pragma once

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <vector>

namespace flagella {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using VecX = Eigen::VectorXd;
using MatX = Eigen::MatrixXd;
using Triplet = Eigen::Triplet<double>;
using TripletList = std::vector<Triplet>;
using SparseMatrix = Eigen::SparseMatrix<double>;

}  // namespace flagella
