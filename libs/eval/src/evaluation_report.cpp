#include "dlo/eval/evaluation_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

namespace dlo::eval {

namespace {

/// metrics.json keeps the keys in the order written, the order users and scripts know.
using Json = nlohmann::ordered_json;

Json statistics(const metrics::ErrorStatistics& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"max", s.max}};
}

std::string rpeKey(size_t delta) {
  return std::to_string(delta) + (delta == 1 ? "_frame" : "_frames");
}

Json kittiJson(const metrics::KittiDriftResult& k, const metrics::KittiDriftParams& params) {
  Json lengths = Json::array();
  Json per_length = Json::array();
  for (const metrics::KittiLengthError& l : k.per_length) {
    lengths.push_back(l.length);
    per_length.push_back({{"length", l.length},
                          {"segments", l.segments},
                          {"translation_percent", l.translation_percent},
                          {"rotation_deg_per_100m", l.rotation_deg_per_100m}});
  }
  return {{"translation_percent", k.translation_percent},
          {"rotation_deg_per_100m", k.rotation_deg_per_100m},
          {"segments", k.segments},
          {"step_frames", params.step},
          {"short_sequence", k.short_sequence},
          {"lengths", std::move(lengths)},
          {"per_length", std::move(per_length)}};
}

std::string fixed(double v, int decimals) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.*f", decimals, v);
  return text;
}

/// Pads or keeps `text` to `width` columns, left- or right-aligned.
std::string cell(const std::string& text, size_t width, bool left = false) {
  if (text.size() >= width) return text;
  const std::string pad(width - text.size(), ' ');
  return left ? text + pad : pad + text;
}

}  // namespace

std::string metricsJson(const ComparisonSettings& settings,
                        const std::vector<LabelledEvaluation>& estimates) {
  Json out;
  out["ground_truth"] = {{"file", settings.ground_truth_file},
                         {"poses", settings.ground_truth_poses}};
  out["settings"] = {{"alignment_requested", metrics::alignmentName(settings.options.alignment)},
                     {"max_dt", settings.max_dt},
                     {"rpe_deltas", settings.options.rpe_deltas}};
  Json list = Json::array();
  for (const LabelledEvaluation& le : estimates) {
    const EstimateEvaluation& ev = le.evaluation;
    Json rpe = Json::object();
    for (const metrics::RpeResult& r : ev.rpe) {
      rpe[rpeKey(r.delta)] = {{"frames", r.delta},
                              {"pairs", r.translation.count},
                              {"translation_m", statistics(r.translation)},
                              {"rotation_deg", statistics(r.rotation)}};
    }
    list.push_back({{"label", le.label},
                    {"file", le.file},
                    {"poses", le.poses},
                    {"matched_poses", ev.matched_poses},
                    {"matching", ev.matching},
                    {"alignment", metrics::alignmentName(ev.ate.alignment)},
                    {"ate", statistics(ev.ate.error)},
                    {"rpe", std::move(rpe)},
                    {"kitti", kittiJson(ev.kitti, settings.options.kitti)}});
  }
  out["estimates"] = std::move(list);
  // File names are the user's bytes: invalid UTF-8 is replaced rather than thrown on.
  return out.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

std::string metricsTable(const ComparisonSettings& settings,
                         const std::vector<LabelledEvaluation>& estimates) {
  size_t label_width = 8;
  for (const LabelledEvaluation& e : estimates) {
    label_width = std::max(label_width, e.label.size() + 2);
  }
  std::ostringstream o;
  o << "ATE after " << metrics::alignmentName(settings.options.alignment)
    << " alignment [m]; RPE rmse over N frames: translation [m], rotation [deg]; KITTI drift: "
       "translation [%], rotation [deg/100 m]\n";
  o << cell("estimate", label_width, true) << cell("matched", 8) << cell("ATE rmse", 10)
    << cell("ATE max", 10);
  for (size_t delta : settings.options.rpe_deltas) {
    o << cell("RPE" + std::to_string(delta) + " t", 10)
      << cell("RPE" + std::to_string(delta) + " r", 9);
  }
  o << cell("KITTI t%", 10) << cell("KITTI r", 9) << "\n";
  for (const LabelledEvaluation& e : estimates) {
    const EstimateEvaluation& ev = e.evaluation;
    o << cell(e.label, label_width, true) << cell(std::to_string(ev.matched_poses), 8)
      << cell(fixed(ev.ate.error.rmse, 3), 10) << cell(fixed(ev.ate.error.max, 3), 10);
    for (const metrics::RpeResult& r : ev.rpe) {
      const bool any = r.translation.count > 0;
      o << cell(any ? fixed(r.translation.rmse, 3) : "-", 10)
        << cell(any ? fixed(r.rotation.rmse, 3) : "-", 9);
    }
    const bool kitti = ev.kitti.segments > 0;
    o << cell(kitti ? fixed(ev.kitti.translation_percent, 2) : "-", 10)
      << cell(kitti ? fixed(ev.kitti.rotation_deg_per_100m, 3) : "-", 9) << "\n";
  }
  // The lengths differ between estimates only when their matched paths do; name them always,
  // since short sequences fall back to fractions of the path.
  for (const LabelledEvaluation& e : estimates) {
    const metrics::KittiDriftResult& k = e.evaluation.kitti;
    o << "KITTI lengths for " << e.label << ":";
    if (k.per_length.empty()) o << " none (the path is too short)";
    for (size_t i = 0; i < k.per_length.size(); ++i) {
      o << (i ? ", " : " ") << fixed(k.per_length[i].length, k.short_sequence ? 1 : 0);
    }
    if (!k.per_length.empty()) {
      o << " m" << (k.short_sequence ? " (fractions of a path shorter than 100 m)" : "");
    }
    o << "\n";
  }
  return o.str();
}

}  // namespace dlo::eval
