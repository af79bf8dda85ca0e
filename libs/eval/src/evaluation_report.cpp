#include "dlo/eval/evaluation_report.h"

#include "dlo/core/json_text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace dlo::eval {

namespace {

std::string jsonNumber(double v) {
  return dlo::jsonNumber(v, 9);
}

std::string statistics(const metrics::ErrorStatistics& s) {
  return "{\"rmse\": " + jsonNumber(s.rmse) + ", \"mean\": " + jsonNumber(s.mean) +
         ", \"median\": " + jsonNumber(s.median) + ", \"max\": " + jsonNumber(s.max) + "}";
}

std::string rpeKey(size_t delta) {
  return std::to_string(delta) + (delta == 1 ? "_frame" : "_frames");
}

void writeKitti(std::ostringstream& o, const metrics::KittiDriftResult& k,
                const metrics::KittiDriftParams& params) {
  o << "    \"kitti\": {\"translation_percent\": " << jsonNumber(k.translation_percent)
    << ", \"rotation_deg_per_100m\": " << jsonNumber(k.rotation_deg_per_100m)
    << ", \"segments\": " << k.segments << ", \"step_frames\": " << params.step
    << ", \"short_sequence\": " << (k.short_sequence ? "true" : "false") << ",\n";
  o << "      \"lengths\": [";
  for (size_t i = 0; i < k.per_length.size(); ++i) {
    o << (i ? ", " : "") << jsonNumber(k.per_length[i].length);
  }
  o << "],\n      \"per_length\": [";
  for (size_t i = 0; i < k.per_length.size(); ++i) {
    const metrics::KittiLengthError& l = k.per_length[i];
    o << (i ? ",\n        " : "\n        ") << "{\"length\": " << jsonNumber(l.length)
      << ", \"segments\": " << l.segments
      << ", \"translation_percent\": " << jsonNumber(l.translation_percent)
      << ", \"rotation_deg_per_100m\": " << jsonNumber(l.rotation_deg_per_100m) << "}";
  }
  o << "]}\n";
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
  std::ostringstream o;
  o << "{\n  \"ground_truth\": {\"file\": " << jsonString(settings.ground_truth_file)
    << ", \"poses\": " << settings.ground_truth_poses << "},\n";
  o << "  \"settings\": {\"alignment_requested\": "
    << jsonString(metrics::alignmentName(settings.options.alignment))
    << ", \"max_dt\": " << jsonNumber(settings.max_dt) << ", \"rpe_deltas\": [";
  for (size_t i = 0; i < settings.options.rpe_deltas.size(); ++i) {
    o << (i ? ", " : "") << settings.options.rpe_deltas[i];
  }
  o << "]},\n  \"estimates\": [";
  for (size_t e = 0; e < estimates.size(); ++e) {
    const LabelledEvaluation& le = estimates[e];
    const EstimateEvaluation& ev = le.evaluation;
    o << (e ? ",\n" : "\n") << "   {\n";
    o << "    \"label\": " << jsonString(le.label) << ",\n";
    o << "    \"file\": " << jsonString(le.file) << ",\n";
    o << "    \"poses\": " << le.poses << ",\n";
    o << "    \"matched_poses\": " << ev.matched_poses << ",\n";
    o << "    \"matching\": " << jsonString(ev.matching) << ",\n";
    o << "    \"alignment\": " << jsonString(metrics::alignmentName(ev.ate.alignment)) << ",\n";
    o << "    \"ate\": " << statistics(ev.ate.error) << ",\n";
    o << "    \"rpe\": {";
    for (size_t i = 0; i < ev.rpe.size(); ++i) {
      const metrics::RpeResult& r = ev.rpe[i];
      o << (i ? ",\n" : "\n") << "      " << jsonString(rpeKey(r.delta))
        << ": {\"frames\": " << r.delta << ", \"pairs\": " << r.translation.count
        << ",\n        \"translation_m\": " << statistics(r.translation)
        << ",\n        \"rotation_deg\": " << statistics(r.rotation) << "}";
    }
    o << "},\n";
    writeKitti(o, ev.kitti, settings.options.kitti);
    o << "   }";
  }
  o << "\n  ]\n}\n";
  return o.str();
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
