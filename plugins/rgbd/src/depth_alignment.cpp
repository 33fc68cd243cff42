#include "depth_alignment.h"

#include <cmath>

#include <Eigen/Eigenvalues>

#include "plugslam/errors.h"

namespace plugslam {
namespace rgbd {

DepthSurface makeDepthSurface(const DepthImage& depth, const CameraIntrinsics& camera, int spacing,
                              double max_step) {
  if (camera.distortion.model != Distortion::Model::kNone)
    throw InputError("makeDepthSurface: the depth camera must be an ideal pinhole");
  if (camera.fx == 0 || camera.fy == 0) throw InputError("makeDepthSurface: zero focal length");
  DepthSurface s;
  s.width = depth.width;
  s.height = depth.height;
  s.camera = camera;
  const size_t n = static_cast<size_t>(depth.width) * static_cast<size_t>(depth.height);
  s.points.assign(n, Eigen::Vector3f::Zero());
  s.normals.assign(n, Eigen::Vector3f::Zero());
  for (int v = 0; v < depth.height; ++v)
    for (int u = 0; u < depth.width; ++u) {
      const float z = depth.at(u, v);
      if (!(z > 0) || !std::isfinite(z)) continue;
      s.points[static_cast<size_t>(v * depth.width + u)] =
          Eigen::Vector3f(static_cast<float>((u - camera.cx) / camera.fx) * z,
                          static_cast<float>((v - camera.cy) / camera.fy) * z, z);
    }
  const auto at = [&](int u, int v) -> const Eigen::Vector3f& {
    return s.points[static_cast<size_t>(v * s.width + u)];
  };
  for (int v = spacing; v + spacing < s.height; ++v)
    for (int u = spacing; u + spacing < s.width; ++u) {
      const Eigen::Vector3f& c = at(u, v);
      if (c.z() <= 0) continue;
      const Eigen::Vector3f& l = at(u - spacing, v);
      const Eigen::Vector3f& r = at(u + spacing, v);
      const Eigen::Vector3f& t = at(u, v - spacing);
      const Eigen::Vector3f& b = at(u, v + spacing);
      const float step = static_cast<float>(max_step) * c.z();
      bool ok = true;
      for (const Eigen::Vector3f* p : {&l, &r, &t, &b})
        ok = ok && p->z() > 0 && std::abs(p->z() - c.z()) <= step;
      if (!ok) continue;
      const Eigen::Vector3f nrm = (r - l).cross(b - t);
      const float len = nrm.norm();
      if (len > 0) s.normals[static_cast<size_t>(v * s.width + u)] = nrm / len;
    }
  return s;
}

long projectOnto(const DepthSurface& surface, const Eigen::Vector3d& x) {
  if (x.z() <= 1e-6) return -1;
  const CameraIntrinsics& k = surface.camera;
  const long u = std::lround(k.fx * x.x() / x.z() + k.cx);
  const long v = std::lround(k.fy * x.y() / x.z() + k.cy);
  if (u < 0 || v < 0 || u >= surface.width || v >= surface.height) return -1;
  const long i = v * surface.width + u;
  return surface.normals[static_cast<size_t>(i)].squaredNorm() > 0 ? i : -1;
}

namespace {

// The pairs at estimate T and, when `eq` is given, their weighted normal equations.
struct Linearisation {
  Eigen::Matrix<double, 6, 6> h = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  int pairs = 0;
  int points = 0;
  double sum_sq = 0;
};

Linearisation linearise(const DepthSurface& fixed, const DepthSurface& moving, const SE3& t,
                        const DepthAlignmentOptions& o) {
  Linearisation out;
  const Eigen::Matrix3d rot = t.linear();
  const Eigen::Vector3d tr = t.translation();
  const int stride = o.stride > 0 ? o.stride : 1;
  for (int v = 0; v < moving.height; v += stride)
    for (int u = 0; u < moving.width; u += stride) {
      const Eigen::Vector3f& pm = moving.points[static_cast<size_t>(v * moving.width + u)];
      if (pm.z() <= 0) continue;
      ++out.points;
      const Eigen::Vector3d p = rot * pm.cast<double>() + tr;
      const long i = projectOnto(fixed, p);
      if (i < 0) continue;
      const Eigen::Vector3f& nf = fixed.normals[static_cast<size_t>(i)];
      const Eigen::Vector3d q = fixed.points[static_cast<size_t>(i)].cast<double>();
      if ((p - q).norm() > o.max_distance) continue;
      const Eigen::Vector3d n = nf.cast<double>();
      const double r = n.dot(p - q);
      const double w = std::abs(r) <= o.huber ? 1.0 : o.huber / std::abs(r);
      Eigen::Matrix<double, 6, 1> j;
      j << p.cross(n), n;  // d r / d (rotation, translation) of a left perturbation
      out.h.noalias() += w * j * j.transpose();
      out.b.noalias() += w * r * j;
      out.sum_sq += r * r;
      ++out.pairs;
    }
  return out;
}

}  // namespace

DepthAlignmentResult alignDepth(const DepthSurface& fixed, const DepthSurface& moving,
                                const SE3& start, const DepthAlignmentOptions& options) {
  DepthAlignmentResult res;
  SE3 t = start;
  Linearisation lin = linearise(fixed, moving, t, options);
  res.points = lin.points;
  res.pairs_initial = lin.pairs;
  res.rms_initial = lin.pairs > 0 ? std::sqrt(lin.sum_sq / lin.pairs) : 0;
  for (int it = 0; it < options.max_iterations && lin.pairs >= 6; ++it) {
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(lin.h);
    if (ldlt.info() != Eigen::Success) break;
    const Eigen::Matrix<double, 6, 1> dx = -ldlt.solve(lin.b);
    if (!dx.allFinite()) break;
    SE3 step = SE3::Identity();
    step.linear() = so3Exp(dx.head<3>());
    step.translation() = dx.tail<3>();
    t = step * t;
    ++res.iterations;
    lin = linearise(fixed, moving, t, options);
    if (dx.norm() < options.min_step) break;
  }
  res.pose = t;
  res.pairs = lin.pairs;
  res.rms = lin.pairs > 0 ? std::sqrt(lin.sum_sq / lin.pairs) : 0;
  if (lin.pairs >= 6) {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eig(lin.h);
    const double top = eig.eigenvalues()(5);
    res.conditioning = top > 0 ? eig.eigenvalues()(0) / top : 0;
    res.ok = res.conditioning > 0 && std::isfinite(res.rms);
  }
  return res;
}

}  // namespace rgbd
}  // namespace plugslam
