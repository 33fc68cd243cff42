#include "plugslam/eval/report.h"

#include <cmath>
#include <initializer_list>
#include <string>

#include "eval/text_file.h"

namespace plugslam {
inline namespace abi_v1 {

using eval_detail::format;

namespace {

std::string jsonNumber(double v) { return std::isfinite(v) ? format("%.9g", v) : "null"; }

// A tiny JSON object writer: keys are fixed identifiers, values numbers, strings or objects.
class JsonObject {
 public:
  JsonObject& add(const std::string& key, double v) { return raw(key, jsonNumber(v)); }
  JsonObject& add(const std::string& key, std::size_t v) { return raw(key, std::to_string(v)); }
  JsonObject& add(const std::string& key, int v) { return raw(key, std::to_string(v)); }
  JsonObject& add(const std::string& key, const std::string& v) {
    return raw(key, "\"" + escape(v) + "\"");
  }
  JsonObject& add(const std::string& key, const JsonObject& v) { return raw(key, v.str()); }
  std::string str() const { return "{" + body_ + "}"; }

 private:
  static std::string escape(const std::string& s) {
    std::string out;
    for (char c : s) {
      if (c == '"' || c == '\\') {
        out += '\\';
        out += c;
      } else if (static_cast<unsigned char>(c) < 0x20) {
        out += format("\\u%04x", c);
      } else {
        out += c;
      }
    }
    return out;
  }
  JsonObject& raw(const std::string& key, const std::string& value) {
    if (!body_.empty()) body_ += ", ";
    body_ += "\"" + escape(key) + "\": " + value;
    return *this;
  }
  std::string body_;
};

JsonObject statsJson(const ErrorStats& s) {
  JsonObject o;
  o.add("rmse", s.rmse).add("mean", s.mean).add("median", s.median).add("std", s.std);
  o.add("min", s.min).add("max", s.max).add("count", s.count);
  return o;
}

JsonObject meanStdJson(const MeanStd& m) {
  JsonObject o;
  o.add("mean", m.mean).add("std", m.std);
  return o;
}

std::string statsTable(const ErrorStats& t, const ErrorStats& r) {
  std::string s = "| statistic | translation (m) | rotation (deg) |\n|---|---|---|\n";
  auto row = [&](const char* name, double a, double b) {
    s += format("| %s | %.6f | %.6f |\n", name, a, b);
  };
  row("rmse", t.rmse, r.rmse);
  row("mean", t.mean, r.mean);
  row("median", t.median, r.median);
  row("std", t.std, r.std);
  row("min", t.min, r.min);
  row("max", t.max, r.max);
  s += format("| count | %zu | %zu |\n", t.count, r.count);
  return s;
}

}  // namespace

std::string toMarkdown(const AteResult& r) {
  std::string s = format("### ATE (alignment: %s", toString(r.alignment).c_str());
  if (r.alignment == Alignment::Sim3) s += format(", scale %.6f", r.transform.scale);
  s += format(", %zu of %zu estimate poses associated)\n\n", r.translation.count, r.estimate_poses);
  return s + statsTable(r.translation, r.rotation_deg);
}

std::string toMarkdown(const RpeResult& r) {
  std::string s =
      format("### RPE (delta %.9g %s, %zu pairs)\n\n", r.delta, toString(r.unit).c_str(), r.pairs);
  s += statsTable(r.translation, r.rotation_deg);
  // Drift relative to the distance travelled: the figure odometry benchmarks quote.
  s += format(
      "\nTranslation in %% of the segment's path length along the reference (%zu segments of "
      "length %.3f m mean, %.3f to %.3f m): rmse %.4f %%, mean %.4f %%, median %.4f %%, "
      "std %.4f %%, max %.4f %%\n",
      r.translation_percent.count, r.length_m.mean, r.length_m.min, r.length_m.max,
      r.translation_percent.rmse, r.translation_percent.mean, r.translation_percent.median,
      r.translation_percent.std, r.translation_percent.max);
  return s;
}

std::string toMarkdown(const RelationResult& r) {
  std::string s =
      format("### Relation metric (%zu of %zu relations used)\n\n", r.used, r.relations);
  s += "Error of each relation (Kuemmerle et al. 2009): E = relation^-1 * (estimate(t1)^-1 * "
       "estimate(t2)); translation |t(E)|, rotation |angle(E)|; mean and sample std.\n";
  s += format("Stamps matched within %.3g s (largest difference %.3g s).\n", r.max_time_diff,
              r.largest_dt);
  if (r.used < r.relations) {
    s += format(
        "Not used: %zu with no estimate pose at t1, %zu none at t2, %zu none at either (no "
        "tracked frame at that stamp, or the estimate is cut short).\n",
        r.missing_t1, r.missing_t2, r.missing_both);
  }
  s += "\n| error | mean | std |\n|---|---|---|\n";
  s += format("| translation (m) | %.6f | %.6f |\n", r.translation.mean, r.translation.std);
  s += format("| translation² (m²) | %.6f | %.6f |\n", r.translation_sq.mean, r.translation_sq.std);
  s += format("| rotation (deg) | %.6f | %.6f |\n", r.rotation_deg.mean, r.rotation_deg.std);
  s +=
      format("| rotation² (deg²) | %.6f | %.6f |\n", r.rotation_sq_deg.mean, r.rotation_sq_deg.std);
  return s;
}

std::string toMarkdown(const CrispnessResult& r) {
  std::string s = "### Crispness\n\n| quantity | value |\n|---|---|\n";
  s += format("| mean nearest distance (m) | %.6f |\n", r.mean);
  s += format("| matched points | %zu of %zu |\n", r.matched_points, r.points);
  s += format("| coverage | %.6f |\n", r.coverage());
  s += format("| scans | %zu |\n", r.scans);
  s += format("| min index gap | %d |\n", r.min_index_gap);
  if (r.max_index_gap > 0) s += format("| max index gap | %d |\n", r.max_index_gap);
  s += format("| radius (m) | %.6g |\n", r.radius);
  return s;
}

// Adds each figure's summary under its key, written by `json` (statsJson or meanStdJson).
template <class S>
void addSummaries(JsonObject& o, JsonObject (*json)(const S&),
                  std::initializer_list<std::pair<const char*, const S*>> named) {
  for (const auto& [key, summary] : named) o.add(key, json(*summary));
}

std::string toJson(const AteResult& r) {
  JsonObject o;
  o.add("metric", std::string("ate")).add("alignment", toString(r.alignment));
  o.add("scale", r.transform.scale);
  o.add("reference_poses", r.reference_poses).add("estimate_poses", r.estimate_poses);
  addSummaries(o, statsJson,
               {{"translation_m", &r.translation}, {"rotation_deg", &r.rotation_deg}});
  return o.str();
}

std::string toJson(const RpeResult& r) {
  JsonObject o;
  o.add("metric", std::string("rpe")).add("unit", toString(r.unit)).add("delta", r.delta);
  o.add("pairs", r.pairs);
  addSummaries(o, statsJson,
               {{"translation_m", &r.translation},
                {"rotation_deg", &r.rotation_deg},
                {"translation_percent", &r.translation_percent},
                {"length_m", &r.length_m}});
  return o.str();
}

std::string toJson(const RelationResult& r) {
  JsonObject o;
  o.add("metric", std::string("relations")).add("relations", r.relations).add("used", r.used);
  o.add("missing_t1", r.missing_t1).add("missing_t2", r.missing_t2);
  o.add("missing_both", r.missing_both);
  o.add("error", std::string("relation^-1 * (estimate(t1)^-1 * estimate(t2))"));
  o.add("max_time_diff_s", r.max_time_diff).add("largest_dt_s", r.largest_dt);
  addSummaries(o, meanStdJson,
               {{"translation_m", &r.translation},
                {"translation_sq_m2", &r.translation_sq},
                {"rotation_deg", &r.rotation_deg},
                {"rotation_sq_deg2", &r.rotation_sq_deg}});
  return o.str();
}

std::string toJson(const CrispnessResult& r) {
  JsonObject o;
  o.add("metric", std::string("crispness")).add("mean_m", r.mean);
  o.add("points", r.points).add("matched_points", r.matched_points).add("coverage", r.coverage());
  o.add("scans", r.scans);
  o.add("min_index_gap", r.min_index_gap)
      .add("max_index_gap", r.max_index_gap)
      .add("radius_m", r.radius);
  return o.str();
}

}  // namespace abi_v1
}  // namespace plugslam
