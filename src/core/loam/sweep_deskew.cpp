#include "ring_curvature/sweep_deskew.hpp"

#include <cmath>

namespace ring_curvature
{

namespace
{
// Rotation by `angle` about the unit axis a (Rodrigues' formula), row-major.
void rotation(const double a[3], double angle, double R[9])
{
  const double c = std::cos(angle), sn = std::sin(angle), C = 1.0 - c;
  const double M[9] = {c + a[0] * a[0] * C,        a[0] * a[1] * C - a[2] * sn, a[0] * a[2] * C + a[1] * sn,
                       a[1] * a[0] * C + a[2] * sn, c + a[1] * a[1] * C,        a[1] * a[2] * C - a[0] * sn,
                       a[2] * a[0] * C - a[1] * sn, a[2] * a[1] * C + a[0] * sn, c + a[2] * a[2] * C};
  for (int i = 0; i < 9; ++i) R[i] = M[i];
}
}  // namespace

void SweepDeskew::prepare(const SweepMotion& motion, double period, double reference)
{
  steps_per_second_ = period > 0 ? static_cast<float>(kSteps / period) : 0.0f;
  const auto& w = motion.rotation;
  const double angle = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
  const double axis[3] = {angle > 0 ? w[0] / angle : 0.0, angle > 0 ? w[1] / angle : 0.0, angle > 0 ? w[2] / angle : 0.0};
  // Constant velocity: at sweep fraction s the pose in the start frame is (R(s angle), s t). In the
  // frame at the reference fraction r: R((s - r) angle) and R(r angle)^T (s - r) t.
  const double r = period > 0 ? reference / period : 0.0;
  double Rr[9];
  rotation(axis, -r * angle, Rr);
  const auto& t = motion.translation;
  const double tr[3] = {Rr[0] * t[0] + Rr[1] * t[1] + Rr[2] * t[2], Rr[3] * t[0] + Rr[4] * t[1] + Rr[5] * t[2],
                        Rr[6] * t[0] + Rr[7] * t[1] + Rr[8] * t[2]};
  for (int k = 0; k <= kSteps; ++k)
  {
    const double s = static_cast<double>(k) / kSteps - r;
    double R[9];
    rotation(axis, s * angle, R);
    std::array<float, 12>& m = table_[static_cast<std::size_t>(k)];
    for (std::size_t i = 0; i < 9; ++i) m[i] = static_cast<float>(R[i]);
    for (std::size_t i = 0; i < 3; ++i) m[9 + i] = static_cast<float>(s * tr[i]);
  }
}

}  // namespace ring_curvature
