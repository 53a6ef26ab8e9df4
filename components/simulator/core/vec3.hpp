#pragma once
// Minimal 3-vector used on the renderer's hot path (float) and in dynamics (double).

#include <cmath>

namespace stereoball::simulator {

/// A 3-vector of T; plain aggregate so arrays of it stay trivially copyable.
template <typename T>
struct Vec3 {
  T x{}, y{}, z{};

  constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3 operator*(T s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr T dot(const Vec3& o) const { return x * o.x + y * o.y + z * o.z; }
  constexpr Vec3 cross(const Vec3& o) const {
    return {y * o.z - z * o.y, z * o.x - x * o.z, x * o.y - y * o.x};
  }
  T norm() const { return std::sqrt(dot(*this)); }
  Vec3 normalized() const {
    const T n = norm();
    return n > T(0) ? *this * (T(1) / n) : *this;
  }
  template <typename U>
  constexpr Vec3<U> cast() const {
    return {static_cast<U>(x), static_cast<U>(y), static_cast<U>(z)};
  }
};

using Vec3d = Vec3<double>;
using Vec3f = Vec3<float>;

/// Row-major 3x3 rotation matrix (double) with the few operations the simulator needs.
struct Mat3 {
  double m[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

  Vec3d operator*(const Vec3d& v) const {
    return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
            m[6] * v.x + m[7] * v.y + m[8] * v.z};
  }
  Mat3 operator*(const Mat3& o) const {
    Mat3 r;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        r.m[i * 3 + j] = m[i * 3] * o.m[j] + m[i * 3 + 1] * o.m[3 + j] + m[i * 3 + 2] * o.m[6 + j];
      }
    }
    return r;
  }
  Mat3 transposed() const { return Mat3{{m[0], m[3], m[6], m[1], m[4], m[7], m[2], m[5], m[8]}}; }
  /// Matrix whose columns are a, b, c.
  static Mat3 from_columns(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    return Mat3{{a.x, b.x, c.x, a.y, b.y, c.y, a.z, b.z, c.z}};
  }
  /// Rotation about the z axis by yaw_rad (counter-clockwise seen from above).
  static Mat3 rot_z(double yaw_rad) {
    const double c = std::cos(yaw_rad), s = std::sin(yaw_rad);
    return Mat3{{c, -s, 0, s, c, 0, 0, 0, 1}};
  }
  /// Rotation by angle |w| about axis w (Rodrigues), w in radians.
  static Mat3 rodrigues(const Vec3d& w) {
    const double th = w.norm();
    if (th < 1e-15) return Mat3{};
    const Vec3d k = w * (1.0 / th);
    const double c = std::cos(th), s = std::sin(th), v = 1.0 - c;
    return Mat3{{c + k.x * k.x * v, k.x * k.y * v - k.z * s, k.x * k.z * v + k.y * s,
                 k.y * k.x * v + k.z * s, c + k.y * k.y * v, k.y * k.z * v - k.x * s,
                 k.z * k.x * v - k.y * s, k.z * k.y * v + k.x * s, c + k.z * k.z * v}};
  }
};

}  // namespace stereoball::simulator
