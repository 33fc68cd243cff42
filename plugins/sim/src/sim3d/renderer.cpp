#include "sim3d/renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "plugslam/errors.h"

namespace plugslam {
namespace sim {
namespace sim3d {
namespace {

constexpr double kEdgeSlack = 1e-9;  // same slack as World::castRay

struct Vec2 {
  double x, y;
};

// Sutherland-Hodgman clip of a polygon (camera frame) against z >= near.
int clipNear(const Eigen::Vector3d* in, int n, double near, Eigen::Vector3d* out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d& a = in[i];
    const Eigen::Vector3d& b = in[(i + 1) % n];
    const bool ia = a.z() >= near, ib = b.z() >= near;
    if (ia) out[m++] = a;
    if (ia != ib) {
      const double t = (near - a.z()) / (b.z() - a.z());
      out[m++] = a + t * (b - a);
    }
  }
  return m;
}

// Directional light from above and one side, plus ambient: faces of different orientation get
// different brightness, so box edges show as intensity edges.
double lighting(const Eigen::Vector3d& n_world) {
  static const Eigen::Vector3d light = Eigen::Vector3d(0.35, 0.55, 0.76).normalized();
  return 0.55 + 0.45 * std::abs(n_world.dot(light));
}

inline uint8_t toByte(double v) {
  return static_cast<uint8_t>(std::clamp(v * 255.0 + 0.5, 0.0, 255.0));
}

}  // namespace

void PinholeCamera::validate() const {
  if (!(fx > 0.0) || !(fy > 0.0) || !std::isfinite(fx) || !std::isfinite(fy))
    throw InputError("sim3d camera: fx and fy must be positive");
  if (!std::isfinite(cx) || !std::isfinite(cy))
    throw InputError("sim3d camera: cx, cy must be finite");
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw InputError("sim3d camera: width and height must be in 1..16384");
}

PinholeCamera PinholeCamera::kitti() { return {718.856, 718.856, 607.1928, 185.2157, 1241, 376}; }

CameraInfo PinholeCamera::info() const {
  CameraInfo c;
  c.setIntrinsics({{fx, fy, cx, cy, width, height}, Distortion{}});
  return c;
}

PinholeCamera PinholeCamera::vga() { return {525.0, 525.0, 319.5, 239.5, 640, 480}; }

void render(const World& world, const PinholeCamera& cam, const Eigen::Isometry3d& T_wc,
            RenderBuffers* buf, Image* image, const RenderOptions& opt) {
  cam.validate();
  const int W = cam.width, H = cam.height;
  const size_t N = static_cast<size_t>(W) * H;
  buf->width = W;
  buf->height = H;
  buf->depth.assign(N, std::numeric_limits<double>::infinity());
  buf->face.assign(N, -1);
  buf->incidence.assign(N, 0.0);

  // Per-column and per-row ray slopes: ray(i, j) = (a[i], b[j], 1).
  std::vector<double> a(W), b(H);
  for (int i = 0; i < W; ++i) a[i] = (i - cam.cx) / cam.fx;
  for (int j = 0; j < H; ++j) b[j] = (j - cam.cy) / cam.fy;

  const Eigen::Isometry3d T_cw = T_wc.inverse();
  const Eigen::Matrix3d R = T_cw.linear();
  const Eigen::Vector3d t = T_cw.translation();
  const auto& faces = world.faces();

  for (const Object& obj : world.objects()) {
    // Cull objects whose bounding box lies outside one frustum plane.
    {
      int out_near = 0, out_far = 0, out_l = 0, out_r = 0, out_t = 0, out_b = 0;
      for (int k = 0; k < 8; ++k) {
        const Eigen::Vector3d c =
            T_cw * obj.bounds.corner(static_cast<Eigen::AlignedBox3d::CornerType>(k));
        out_near += c.z() < opt.near;
        out_far += c.z() > opt.far;
        out_l += cam.fx * c.x() + (cam.cx + 0.5) * c.z() < 0.0;
        out_r += cam.fx * c.x() + (cam.cx - W + 0.5) * c.z() > 0.0;
        out_t += cam.fy * c.y() + (cam.cy + 0.5) * c.z() < 0.0;
        out_b += cam.fy * c.y() + (cam.cy - H + 0.5) * c.z() > 0.0;
      }
      if (out_near == 8 || out_far == 8 || out_l == 8 || out_r == 8 || out_t == 8 || out_b == 8)
        continue;
    }
    for (int fi = obj.first_face; fi < obj.first_face + obj.face_count; ++fi) {
      const Face& f = faces[fi];
      const Eigen::Vector3d o = R * f.origin + t;
      const Eigen::Vector3d n = R * f.normal;
      const Eigen::Vector3d u = R * f.u, v = R * f.v;
      const double nd = n.dot(o);               // plane: n . X = nd
      if (!f.two_sided && nd >= 0.0) continue;  // camera behind a one-sided face
      if (nd == 0.0) continue;                  // camera in the plane: seen edge-on
      Eigen::Vector3d poly[4] = {o, o + f.width * u, o + f.width * u + f.height * v,
                                 o + f.height * v};
      Eigen::Vector3d clipped[8];
      const int m = clipNear(poly, 4, opt.near, clipped);
      if (m < 3) continue;
      Vec2 q[8];
      double ymin = 1e300, ymax = -1e300;
      for (int k = 0; k < m; ++k) {
        q[k] = {cam.fx * clipped[k].x() / clipped[k].z() + cam.cx,
                cam.fy * clipped[k].y() / clipped[k].z() + cam.cy};
        ymin = std::min(ymin, q[k].y);
        ymax = std::max(ymax, q[k].y);
      }
      const int j0 = std::max(0, static_cast<int>(std::floor(ymin - 0.5)));
      const int j1 = std::min(H - 1, static_cast<int>(std::ceil(ymax + 0.5)));
      const double uo = u.dot(o), vo = v.dot(o);
      for (int j = j0; j <= j1; ++j) {
        // x-range of the polygon within the strip [j - 0.5, j + 0.5]: conservative, since the
        // exact inside test below decides.
        const double lo = j - 0.5, hi = j + 0.5;
        double xmin = 1e300, xmax = -1e300;
        for (int k = 0; k < m; ++k) {
          const Vec2 p = q[k], r = q[(k + 1) % m];
          if (p.y >= lo && p.y <= hi) {
            xmin = std::min(xmin, p.x);
            xmax = std::max(xmax, p.x);
          }
          for (double yl : {lo, hi}) {
            if ((p.y < yl) != (r.y < yl)) {
              const double x = p.x + (yl - p.y) / (r.y - p.y) * (r.x - p.x);
              xmin = std::min(xmin, x);
              xmax = std::max(xmax, x);
            }
          }
        }
        if (xmin > xmax) continue;
        const int i0 = std::max(0, static_cast<int>(std::floor(xmin)) - 1);
        const int i1 = std::min(W - 1, static_cast<int>(std::ceil(xmax)) + 1);
        const double bj = b[j];
        const double n_row = n.y() * bj + n.z();
        const double u_row = u.y() * bj + u.z();
        const double v_row = v.y() * bj + v.z();
        double* depth = &buf->depth[static_cast<size_t>(j) * W];
        int32_t* ids = &buf->face[static_cast<size_t>(j) * W];
        for (int i = i0; i <= i1; ++i) {
          const double nr = n.x() * a[i] + n_row;
          if (nr == 0.0) continue;
          const double z = nd / nr;
          if (!(z >= opt.near) || !(z < depth[i])) continue;
          const double s = z * (u.x() * a[i] + u_row) - uo;
          if (s < -kEdgeSlack || s > f.width + kEdgeSlack) continue;
          const double tt = z * (v.x() * a[i] + v_row) - vo;
          if (tt < -kEdgeSlack || tt > f.height + kEdgeSlack) continue;
          depth[i] = z;
          ids[i] = fi;
        }
      }
    }
  }

  // Resolve: depth 0 for no hit, incidence, and shading.
  const bool shade = image && opt.shade;
  const int channels = shade ? (image->channels == 1 ? 1 : 3) : 0;
  if (shade) image->resize(W, H, channels);
  std::vector<double> face_light(shade ? faces.size() : 0);
  for (size_t k = 0; k < face_light.size(); ++k) face_light[k] = lighting(faces[k].normal);
  const Eigen::Matrix3d R_wc = T_wc.linear();
  const Eigen::Vector3d c_w = T_wc.translation();
  const Eigen::Vector3d r0 = R_wc.col(0);
  for (int j = 0; j < H; ++j) {
    uint8_t* row = shade ? &image->data[static_cast<size_t>(j) * image->stride] : nullptr;
    const Eigen::Vector3d ray_row = b[j] * R_wc.col(1) + R_wc.col(2);
    for (int i = 0; i < W; ++i) {
      const size_t p = static_cast<size_t>(j) * W + i;
      const int fi = buf->face[p];
      if (fi < 0) {
        buf->depth[p] = 0.0;
        if (shade) {
          // Sky: a plain vertical gradient (no features).
          const double g = 0.75 + 0.2 * j / H;
          if (channels == 1) {
            row[i] = toByte(g);
          } else {
            row[3 * i] = toByte(0.75 * g);
            row[3 * i + 1] = toByte(0.85 * g);
            row[3 * i + 2] = toByte(g);
          }
        }
        continue;
      }
      const Face& f = faces[fi];
      const double z = buf->depth[p];
      const Eigen::Vector3d ray_w = a[i] * r0 + ray_row;
      const double ray_norm = ray_w.norm();
      buf->incidence[p] = std::abs(f.normal.dot(ray_w)) / ray_norm;
      if (!shade) continue;
      const Eigen::Vector3d pw = c_w + z * ray_w;
      const Eigen::Vector3d q = pw - f.origin;
      // One pixel's size on the surface: the distance over the focal length, stretched at
      // oblique incidence (capped so grazing floors keep some texture).
      const double footprint = ray_norm * z / cam.fx / std::max(buf->incidence[p], 0.25);
      const Eigen::Vector3d rgb =
          albedo(f.material, f.u.dot(q), f.v.dot(q), pw, footprint) * face_light[fi];
      if (channels == 1) {
        row[i] = toByte(0.299 * rgb.x() + 0.587 * rgb.y() + 0.114 * rgb.z());
      } else {
        row[3 * i] = toByte(rgb.x());
        row[3 * i + 1] = toByte(rgb.y());
        row[3 * i + 2] = toByte(rgb.z());
      }
    }
  }
}

}  // namespace sim3d
}  // namespace sim
}  // namespace plugslam
