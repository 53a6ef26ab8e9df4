#pragma once
// The shift register of the last N 3D positions (paper section IV) and its
// statistics: mean, covariance, and the 3D best-fit line.

#include <Eigen/Core>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace stereoball::tracker {

/// A position with the capture stamp of its frame.
struct StampedPosition {
  Eigen::Vector3d position_m;  ///< metres, left rectified camera frame
  std::int64_t stamp_ns = 0;   ///< capture stamp, ns
};

/// Distribution of the register: mean, covariance and best-fit line.
struct RegisterStats {
  Eigen::Vector3d mean_m;          ///< mean position, metres
  Eigen::Matrix3d covariance_m2;   ///< population covariance (divided by N), m^2
  double sigma_m = 0.0;            ///< sqrt(trace(cov)): RMS distance of the points to the mean, m
  Eigen::Vector3d line_direction;  ///< unit direction of the best-fit line (through the mean)
  double line_rms_m = 0.0;         ///< RMS perpendicular distance of the points to the line, m
  double line_extent_m = 0.0;      ///< RMS spread of the points along the line, m
};

/// Fixed-capacity FIFO of positions; pushing into a full register drops the oldest.
class PositionRegister {
 public:
  /// capacity: number of positions kept (paper: five).
  explicit PositionRegister(int capacity);

  /// Shifts a position in, dropping the oldest when full.
  void push(const Eigen::Vector3d& position_m, std::int64_t stamp_ns);
  /// Empties the register.
  void clear() { entries_.clear(); }
  /// Number of stored positions.
  int size() const { return static_cast<int>(entries_.size()); }
  /// Positions it holds when full.
  int capacity() const { return capacity_; }
  /// True when size() == capacity.
  bool full() const { return size() == capacity_; }
  /// Stored positions, oldest first.
  const std::vector<StampedPosition>& entries() const { return entries_; }
  /// Mean, covariance and best-fit line; nullopt with fewer than two positions.
  std::optional<RegisterStats> stats() const;

 private:
  int capacity_;
  std::vector<StampedPosition> entries_;  // oldest first; a handful, so erase(begin) is cheap
};

/// Mean, covariance and best-fit line of points; nullopt with fewer than two.
std::optional<RegisterStats> compute_stats(std::span<const StampedPosition> points);

/// Perpendicular distance of p to the line through point with unit direction, metres.
double distance_to_line(const Eigen::Vector3d& p, const Eigen::Vector3d& point,
                        const Eigen::Vector3d& unit_direction);

}  // namespace stereoball::tracker
