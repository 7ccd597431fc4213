#pragma once
// Basic numeric types shared by every module. SI units everywhere inside the code.
#include <Eigen/Dense>
#include <array>
#include <cstdint>

namespace dsdem {

using Index = std::int32_t;
using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;
using Vec3 = Eigen::Vector3d;  // Voigt 2D tensors: (xx, yy, xy)
using Mat3 = Eigen::Matrix3d;
using Vec6 = Eigen::Matrix<double, 6, 1>;  // Voigt 3D tensors: (xx, yy, zz, yz, xz, xy)
// A point or vector of a model of dimension D (2: plane sections, 3: volumes).
template <int D>
using VecD = Eigen::Matrix<double, D, 1>;

constexpr Index kNoIndex = -1;
constexpr double kPi = 3.14159265358979323846;
constexpr double kStandardGravity = 9.80665;  // m/s^2, used when accelerograms are in g

}  // namespace dsdem
