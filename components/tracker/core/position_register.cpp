#include "tracker/core/position_register.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace stereoball::tracker {

PositionRegister::PositionRegister(int capacity) : capacity_(std::max(capacity, 1)) {}

void PositionRegister::push(const Eigen::Vector3d& position_m, std::int64_t stamp_ns) {
  if (full()) entries_.erase(entries_.begin());
  entries_.push_back({position_m, stamp_ns});
}

std::optional<RegisterStats> PositionRegister::stats() const {
  return compute_stats(entries_);
}

std::optional<RegisterStats> compute_stats(std::span<const StampedPosition> points) {
  if (points.size() < 2) return std::nullopt;
  const double n = static_cast<double>(points.size());
  RegisterStats s;
  s.mean_m.setZero();
  for (const auto& e : points) s.mean_m += e.position_m;
  s.mean_m /= n;
  s.covariance_m2.setZero();
  for (const auto& e : points) {
    const Eigen::Vector3d d = e.position_m - s.mean_m;
    s.covariance_m2 += d * d.transpose();
  }
  s.covariance_m2 /= n;
  s.sigma_m = std::sqrt(std::max(0.0, s.covariance_m2.trace()));
  // Eigenvalues come sorted ascending: the last eigenvector is the principal
  // direction, and the two smaller eigenvalues are the mean squared
  // perpendicular distances to the line through the mean along it.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(s.covariance_m2);
  s.line_direction = eig.eigenvectors().col(2).normalized();
  const Eigen::Vector3d ev = eig.eigenvalues();
  s.line_rms_m = std::sqrt(std::max(0.0, ev(0) + ev(1)));
  s.line_extent_m = std::sqrt(std::max(0.0, ev(2)));
  return s;
}

double distance_to_line(const Eigen::Vector3d& p, const Eigen::Vector3d& point,
                        const Eigen::Vector3d& unit_direction) {
  const Eigen::Vector3d d = p - point;
  return (d - d.dot(unit_direction) * unit_direction).norm();
}

}  // namespace stereoball::tracker
