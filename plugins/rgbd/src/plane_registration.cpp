#include "plane_registration.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>

namespace plugslam {
namespace rgbd {

std::vector<DepthPlane> extractPlanes(const DepthSurface& s, const DepthNoiseModel& noise,
                                      const PlaneRegistrationOptions& o) {
  const size_t n = s.points.size();
  std::vector<char> used(n, 0);
  size_t readings = 0;
  for (size_t i = 0; i < n; ++i) readings += s.normals[i].squaredNorm() > 0 ? 1 : 0;
  const double cos_max = std::cos(o.max_angle);
  std::vector<DepthPlane> planes;
  std::vector<size_t> region, queue;
  for (size_t start = 0; start < n; ++start) {
    if (used[start] || s.normals[start].squaredNorm() == 0) continue;
    // Region growing from `start`: a neighbour joins when its normal agrees with the region's
    // mean and its point lies on the region's plane (so a gentle curve does not creep on).
    region.clear();
    queue.assign(1, start);
    used[start] = 1;
    Eigen::Vector3d sum_p = Eigen::Vector3d::Zero(), sum_n = Eigen::Vector3d::Zero();
    while (!queue.empty()) {
      const size_t i = queue.back();
      queue.pop_back();
      region.push_back(i);
      sum_p += s.points[i].cast<double>();
      sum_n += s.normals[i].cast<double>();
      const Eigen::Vector3d mean_n = sum_n.normalized();
      const Eigen::Vector3d centroid = sum_p / static_cast<double>(region.size());
      const int u = static_cast<int>(i % static_cast<size_t>(s.width));
      const int v = static_cast<int>(i / static_cast<size_t>(s.width));
      const int du[4] = {1, -1, 0, 0}, dv[4] = {0, 0, 1, -1};
      for (int k = 0; k < 4; ++k) {
        const int x = u + du[k], y = v + dv[k];
        if (x < 0 || y < 0 || x >= s.width || y >= s.height) continue;
        const size_t j = static_cast<size_t>(y) * static_cast<size_t>(s.width) +
                         static_cast<size_t>(x);
        if (used[j] || s.normals[j].squaredNorm() == 0) continue;
        const Eigen::Vector3d p = s.points[j].cast<double>();
        if (s.normals[j].cast<double>().dot(mean_n) < cos_max) continue;
        if (std::abs(mean_n.dot(p - centroid)) > o.max_distance + 3.0 * noise.sigma(p.z()))
          continue;
        used[j] = 1;
        queue.push_back(j);
      }
    }
    if (static_cast<double>(region.size()) < o.min_share * static_cast<double>(readings) ||
        region.size() < 3)
      continue;
    // The plane through the region's points (its least-spread direction).
    DepthPlane plane;
    plane.support = static_cast<int>(region.size());
    plane.centroid = sum_p / static_cast<double>(region.size());
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (size_t i : region) {
      const Eigen::Vector3d d = s.points[i].cast<double>() - plane.centroid;
      scatter.noalias() += d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
    plane.n = eig.eigenvectors().col(0).normalized();
    if (plane.n.dot(plane.centroid) > 0) plane.n = -plane.n;  // towards the camera
    plane.d = plane.n.dot(plane.centroid);
    planes.push_back(plane);
  }
  std::sort(planes.begin(), planes.end(),
            [](const DepthPlane& a, const DepthPlane& b) { return a.support > b.support; });
  if (planes.size() > static_cast<size_t>(o.max_planes))
    planes.resize(static_cast<size_t>(o.max_planes));
  return planes;
}

namespace {

// The spacing of an even grid of about check_points of the moving image's readings (0: none).
int checkStep(const DepthSurface& moving, const PlaneRegistrationOptions& o) {
  size_t readings = 0;
  for (const Eigen::Vector3f& nm : moving.normals) readings += nm.squaredNorm() > 0 ? 1 : 0;
  if (readings == 0) return 0;
  return std::max(
      1, static_cast<int>(std::sqrt(static_cast<double>(readings) / std::max(1, o.check_points))));
}

SurfaceAgreement checkOnGrid(const DepthSurface& fixed, const DepthSurface& moving, const SE3& t,
                             const DepthNoiseModel& noise, const PlaneRegistrationOptions& o,
                             int step) {
  SurfaceAgreement a;
  if (step <= 0 || fixed.width == 0) return a;
  const double cos_normal = std::cos(2.0 * o.max_angle);
  const CameraIntrinsics& k = fixed.camera;
  for (int v = 0; v < moving.height; v += step)
    for (int u = 0; u < moving.width; u += step) {
      const size_t i = static_cast<size_t>(v) * static_cast<size_t>(moving.width) +
                       static_cast<size_t>(u);
      if (moving.normals[i].squaredNorm() == 0) continue;
      ++a.checked;
      const Eigen::Vector3d x = t * moving.points[i].cast<double>();
      if (x.z() <= 1e-6) continue;
      const long pu = std::lround(k.fx * x.x() / x.z() + k.cx);
      const long pv = std::lround(k.fy * x.y() / x.z() + k.cy);
      if (pu < 0 || pv < 0 || pu >= fixed.width || pv >= fixed.height) continue;
      const size_t j = static_cast<size_t>(pv * fixed.width + pu);
      const Eigen::Vector3d q = fixed.points[j].cast<double>();
      if (q.z() <= 0) continue;  // the fixed camera has no reading there: it cannot judge
      const double tol = o.max_distance + 3.0 * (noise.sigma(x.z()) + noise.sigma(q.z()));
      // Along the fixed camera's ray: nearer than what it saw is space it saw through.
      if (x.z() < q.z() - tol) {
        ++a.in_front;
        continue;
      }
      const Eigen::Vector3f& nq = fixed.normals[j];
      if (nq.squaredNorm() == 0) continue;
      const Eigen::Vector3d nqd = nq.cast<double>();
      if (std::abs(nqd.dot(x - q)) <= tol &&
          (t.linear() * moving.normals[i].cast<double>()).dot(nqd) >= cos_normal)
        ++a.on;
    }
  return a;
}

}  // namespace

SurfaceAgreement checkAgreement(const DepthSurface& fixed, const DepthSurface& moving,
                                const SE3& t, const DepthNoiseModel& noise,
                                const PlaneRegistrationOptions& o) {
  return checkOnGrid(fixed, moving, t, noise, o, checkStep(moving, o));
}

namespace {

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0));
}

double spread(const DepthPlane& a, const DepthPlane& b, const DepthPlane& c) {
  Eigen::Matrix3d m;
  m << a.n, b.n, c.n;
  return std::abs(m.determinant());
}

}  // namespace

std::vector<PlaneHypothesis> registerPlanes(const DepthSurface& fixed,
                                            const std::vector<DepthPlane>& fp,
                                            const DepthSurface& moving,
                                            const std::vector<DepthPlane>& mp,
                                            const DepthNoiseModel& noise,
                                            const PlaneRegistrationOptions& o) {
  std::vector<PlaneHypothesis> out;
  const size_t nm = mp.size(), nf = fp.size();
  const int step = checkStep(moving, o);  // the same points check every hypothesis
  const double cos_max = std::cos(o.max_angle);
  for (size_t a = 0; a < nm; ++a)
    for (size_t b = a + 1; b < nm; ++b)
      for (size_t c = b + 1; c < nm; ++c) {
        if (spread(mp[a], mp[b], mp[c]) < o.min_spread) continue;
        const DepthPlane* m[3] = {&mp[a], &mp[b], &mp[c]};
        const double ab = angleBetween(m[0]->n, m[1]->n), ac = angleBetween(m[0]->n, m[2]->n),
                     bc = angleBetween(m[1]->n, m[2]->n);
        for (size_t i = 0; i < nf; ++i)
          for (size_t j = 0; j < nf; ++j)
            for (size_t k = 0; k < nf; ++k) {
              if (i == j || i == k || j == k) continue;
              const DepthPlane* f[3] = {&fp[i], &fp[j], &fp[k]};
              // The angles between three planes are the same from every viewpoint.
              if (std::abs(angleBetween(f[0]->n, f[1]->n) - ab) > o.max_angle ||
                  std::abs(angleBetween(f[0]->n, f[2]->n) - ac) > o.max_angle ||
                  std::abs(angleBetween(f[1]->n, f[2]->n) - bc) > o.max_angle ||
                  spread(*f[0], *f[1], *f[2]) < o.min_spread)
                continue;
              // The rotation taking the moving normals onto the fixed ones (Kabsch), weighted
              // by support, proper (a mirror image of the corner is no pose).
              Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
              for (int q = 0; q < 3; ++q)
                h.noalias() += std::min(m[q]->support, f[q]->support) * m[q]->n *
                               f[q]->n.transpose();
              const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU |
                                                                 Eigen::ComputeFullV);
              Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
              d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
              const Eigen::Matrix3d r = svd.matrixV() * d * svd.matrixU().transpose();
              bool agree = true;
              for (int q = 0; q < 3; ++q) agree = agree && (r * m[q]->n).dot(f[q]->n) >= cos_max;
              if (!agree) continue;
              // Each plane pair fixes the translation along its normal: n_f . t = d_f - d_m.
              Eigen::Matrix3d rows;
              Eigen::Vector3d rhs;
              for (int q = 0; q < 3; ++q) {
                rows.row(q) = f[q]->n.transpose();
                rhs(q) = f[q]->d - m[q]->d;
              }
              PlaneHypothesis hyp;
              hyp.pose.linear() = r;
              hyp.pose.translation() = rows.colPivHouseholderQr().solve(rhs);
              if (!hyp.pose.translation().allFinite()) continue;
              hyp.planes = 3;
              hyp.agreement = checkOnGrid(fixed, moving, hyp.pose, noise, o, step);
              out.push_back(hyp);
            }
      }
  const auto score = [](const PlaneHypothesis& h) {
    return h.agreement.on - h.agreement.in_front;
  };
  std::stable_sort(out.begin(), out.end(), [&](const PlaneHypothesis& x, const PlaneHypothesis& y) {
    return score(x) > score(y);
  });
  return out;
}

}  // namespace rgbd
}  // namespace plugslam
