#include "plugslam/eval/relations.h"

#include <algorithm>
#include <cmath>

#include "eval/text_file.h"
#include "plugslam/atomic_file.h"
#include "plugslam/errors.h"

namespace plugslam {
inline namespace abi_v1 {

using eval_detail::format;

namespace {
constexpr double kRadToDeg = 180.0 / M_PI;

Eigen::Isometry3d fromXyzRpy(double x, double y, double z, double roll, double pitch, double yaw) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  t.translation() = Eigen::Vector3d(x, y, z);
  return t;
}

void toRpy(const Eigen::Matrix3d& r, double& roll, double& pitch, double& yaw) {
  // R = Rz(yaw) Ry(pitch) Rx(roll).
  pitch = std::asin(std::max(-1.0, std::min(1.0, -r(2, 0))));
  roll = std::atan2(r(2, 1), r(2, 2));
  yaw = std::atan2(r(1, 0), r(0, 0));
}
}  // namespace

std::vector<Relation> readRelations(const std::string& path) {
  std::vector<Relation> relations;
  static const char* kNames[] = {"t1", "t2", "x", "y", "z", "roll", "pitch", "yaw"};
  for (const eval_detail::TextLine& line : eval_detail::readDataLines(path)) {
    if (line.tokens.size() != 8) {
      throw ParseError(
          path, line.number,
          format("expected 8 columns (t1 t2 x y z roll pitch yaw), got %zu", line.tokens.size()));
    }
    double v[8];
    for (std::size_t i = 0; i < 8; ++i) v[i] = eval_detail::parseNumber(path, line, i, kNames[i]);
    relations.push_back(Relation{v[0], v[1], fromXyzRpy(v[2], v[3], v[4], v[5], v[6], v[7])});
  }
  if (relations.empty()) {
    throw ParseError(path, 0, "no relations found: expected lines 't1 t2 x y z roll pitch yaw'");
  }
  return relations;
}

void writeRelations(const std::vector<Relation>& relations, const std::string& path) {
  std::string text = "# t1 t2 x y z roll pitch yaw\n";
  for (const Relation& r : relations) {
    double roll, pitch, yaw;
    toRpy(r.delta.linear(), roll, pitch, yaw);
    const Eigen::Vector3d t = r.delta.translation();
    text += format("%.9f %.9f %.10g %.10g %.10g %.10g %.10g %.10g\n", r.t1, r.t2, t.x(), t.y(),
                   t.z(), roll, pitch, yaw);
  }
  writeFileAtomically(path, text);
}

std::vector<Relation> relationsFromTrajectory(const Trajectory& reference, double max_distance) {
  if (reference.size() < 2) {
    throw InputError("relations need a reference trajectory with at least 2 poses");
  }
  std::vector<Relation> relations;
  const double max_sq = max_distance * max_distance;
  for (std::size_t i = 0; i + 1 < reference.size(); ++i) {
    const StampedPose& a = reference[i];
    for (std::size_t j = i + 1; j < reference.size(); ++j) {
      const StampedPose& b = reference[j];
      const bool consecutive = j == i + 1;
      if (!consecutive && (max_distance <= 0.0 ||
                           (b.pose.translation() - a.pose.translation()).squaredNorm() > max_sq)) {
        continue;
      }
      relations.push_back(Relation{a.t, b.t, a.pose.inverse() * b.pose});
    }
  }
  return relations;
}

Eigen::Isometry3d relationError(const Relation& relation, const Eigen::Isometry3d& p1,
                                const Eigen::Isometry3d& p2) {
  // The benchmark's delta_ij (-) delta*_ij, with a (-) b = b^-1 a: the estimate's motion seen
  // from the relation's end. Its translation is the difference of the two motions' translations
  // in the frame of t1, not lever-armed by the rotation error as (p1^-1 p2) delta^-1 would be.
  return relation.delta.inverse() * (p1.inverse() * p2);
}

RelationResult evaluateRelations(const Trajectory& estimate, const std::vector<Relation>& relations,
                                 const RelationOptions& options) {
  if (relations.empty()) throw InputError("no relations to evaluate");
  if (estimate.empty()) throw InputError("cannot evaluate relations: the estimate is empty");
  if (!(options.max_time_diff >= 0.0)) throw InputError("relations need a time tolerance >= 0 s");
  RelationResult result;
  result.relations = relations.size();
  result.max_time_diff = options.max_time_diff;
  std::vector<double> trans, trans_sq, rot, rot_sq;
  double first = relations.front().t1, last = relations.front().t1;
  for (const Relation& r : relations) {
    first = std::min({first, r.t1, r.t2});
    last = std::max({last, r.t1, r.t2});
    const auto i = estimate.nearest(r.t1, options.max_time_diff);
    const auto j = estimate.nearest(r.t2, options.max_time_diff);
    if (!i || !j) {
      ++(!i && !j ? result.missing_both : !i ? result.missing_t1 : result.missing_t2);
      continue;
    }
    result.largest_dt = std::max(
        {result.largest_dt, std::abs(estimate[*i].t - r.t1), std::abs(estimate[*j].t - r.t2)});
    const Eigen::Isometry3d e = relationError(r, estimate[*i].pose, estimate[*j].pose);
    const double t = e.translation().norm();
    const double a = Eigen::AngleAxisd(e.linear()).angle() * kRadToDeg;
    trans.push_back(t);
    trans_sq.push_back(t * t);
    rot.push_back(a);
    rot_sq.push_back(a * a);
  }
  if (trans.empty()) {
    throw InputError(format(
        "no overlap: relations span [%.9g, %.9g], estimate spans [%.9g, %.9g]: no relation has "
        "both timestamps within %.9g s of an estimate pose (%zu miss t1, %zu t2, %zu both)",
        first, last, estimate.startTime(), estimate.endTime(), options.max_time_diff,
        result.missing_t1, result.missing_t2, result.missing_both));
  }
  result.used = trans.size();
  result.translation = computeMeanStd(trans);
  result.translation_sq = computeMeanStd(trans_sq);
  result.rotation_deg = computeMeanStd(rot);
  result.rotation_sq_deg = computeMeanStd(rot_sq);
  return result;
}

}  // namespace abi_v1
}  // namespace plugslam
