#include "inspect/diff.h"

#include <iomanip>
#include <map>
#include <sstream>

namespace nightcap {
namespace {

std::string number(double v, int precision = 4) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream s;
  s << std::setprecision(precision) << v;
  return s.str();
}

const PassRecord* find(const FrameRecord& frame, const std::string& name) {
  for (const PassRecord& p : frame.passes)
    if (p.name == name) return &p;
  return nullptr;
}

std::map<std::string, std::string> hashes(const std::vector<ResourceRecord>& records) {
  std::map<std::string, std::string> out;
  for (const ResourceRecord& r : records) out[r.resource] = r.hash;
  return out;
}

std::map<std::string, std::string> shader_hashes(const PassRecord& p) {
  std::map<std::string, std::string> out;
  for (const ShaderRecord& s : p.shaders) out[s.path] = s.hash;
  return out;
}

// Outputs `--tolerance` applies to: float colour values (not normals, depth or buffers).
bool float_output(const ResourceRecord& r) {
  if (r.is_buffer || r.kind == ResourceKind::normal || r.kind == ResourceKind::packed_normal) return false;
  const FormatInfo f = *format_info(r.format);
  return !f.is_depth && (f.encoding == ChannelEncoding::sfloat16 || f.encoding == ChannelEncoding::sfloat32 ||
                         f.encoding == ChannelEncoding::packed_b10g11r11);
}

// What one side lacks, named for the side: capture A or B, or against a golden (A) the output.
void mark_only_in(OutputDiff& o, bool in_a, bool golden) {
  o.only_in_one = true;
  o.comparison.comparable = false;
  o.comparison.note = golden ? (in_a ? "output missing" : "golden missing") : (in_a ? "only in A" : "only in B");
  if (golden) o.missing = in_a ? "output" : "golden";
}

PassDiff diff_pass(const Capture& ca, const FrameRecord& frame_a, const PassRecord& a, const Capture& cb,
                   const PassRecord& b, const DiffOptions& options) {
  PassDiff d;
  d.name = a.name;
  if (!a.ran || !b.ran) {
    d.status = !a.ran && !b.ran ? PassStatus::skipped : !a.ran ? PassStatus::skipped_in_a : PassStatus::skipped_in_b;
    d.beyond_tolerance = a.ran != b.ran;
    return d;
  }
  d.inputs_agree = hashes(a.inputs) == hashes(b.inputs);
  d.params_agree = a.params == b.params;
  d.shaders_agree = shader_hashes(a) == shader_hashes(b);
  bool differs = false;
  for (const ResourceRecord& ra : a.outputs) {
    OutputDiff o;
    o.resource = ra.resource;
    const ResourceRecord* rb = nullptr;
    for (const ResourceRecord& r : b.outputs)
      if (r.resource == ra.resource) rb = &r;
    if (!rb) {
      mark_only_in(o, true, options.golden);
      differs = d.beyond_tolerance = true;
    } else {
      const ThresholdRule* rule = options.thresholds ? options.thresholds->match(a.name, ra) : nullptr;
      const bool by_tolerance = !rule && options.tolerance && float_output(ra);
      o.held_to = rule           ? rule->description() + " (" + rule->source + ")"
                  : by_tolerance ? "max abs <= " + number(*options.tolerance) + " (--tolerance)"
                                 : contract_description(ra.contract) + " (recorded contract)";
      if (ra.hash == rb->hash) {
        o.comparison.identical = true;
        o.comparison.metric = "bytes";
        d.outputs.push_back(std::move(o));
        continue;
      }
      const std::vector<uint8_t> raw_a = ca.load(ra), raw_b = cb.load(*rb);
      o.comparison = compare_resource(ra, raw_a, *rb, raw_b);
      differs = true;
      if (o.comparison.comparable && displayed_colour(ra)) o.flip = flip_displayed(ra, raw_a, raw_b);
      if (rule) {
        o.threshold = o.comparison.comparable
                          ? check_threshold(*rule, frame_a, ra, raw_a, raw_b,
                                            o.flip ? std::span<const float>(o.flip->error) : std::span<const float>())
                          : ThresholdCheck{false, 0, 0, INFINITY, o.comparison.note};
        o.beyond = !o.threshold->holds;
      } else if (by_tolerance) {
        o.beyond = !o.comparison.comparable || !(o.comparison.max_abs <= *options.tolerance);
      } else {
        o.contract = check_contract(ra.contract, ra, raw_a, raw_b, o.comparison);
        o.beyond = !o.contract.holds;
      }
      if (o.beyond) d.beyond_tolerance = true;
    }
    d.outputs.push_back(std::move(o));
  }
  const auto outputs_a = hashes(a.outputs);
  for (const ResourceRecord& rb : b.outputs)
    if (!outputs_a.count(rb.resource)) {
      OutputDiff o;
      o.resource = rb.resource;
      mark_only_in(o, false, options.golden);
      d.outputs.push_back(std::move(o));
      differs = d.beyond_tolerance = true;
    }
  // Equal inputs but different outputs: the change entered here (through a parameter, a
  // shader, or the pass's own behaviour); params_agree and shaders_agree say which.
  if (differs) d.status = d.inputs_agree ? PassStatus::origin : PassStatus::inherited;
  return d;
}

nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

std::string status_name(PassStatus status) {
  switch (status) {
    case PassStatus::identical:
      return "identical";
    case PassStatus::origin:
      return "origin";
    case PassStatus::inherited:
      return "inherited";
    case PassStatus::skipped:
      return "skipped";
    case PassStatus::skipped_in_a:
      return "skipped_in_a";
    case PassStatus::skipped_in_b:
      return "skipped_in_b";
    case PassStatus::only_in_a:
      return "only_in_a";
    case PassStatus::only_in_b:
      return "only_in_b";
  }
  return "";
}

std::string status_name(PassStatus status, bool golden) {
  if (golden && status == PassStatus::only_in_a) return "output_missing";
  if (golden && status == PassStatus::only_in_b) return "golden_missing";
  return status_name(status);
}

CaptureDiff diff_captures(const Capture& a, const Capture& b, const DiffOptions& options) {
  CaptureDiff diff;
  diff.golden = options.golden;
  const std::string only_in_a = options.golden ? ": output missing" : " only in A",
                    only_in_b = options.golden ? ": golden missing" : " only in B";
  if (options.frame) {
    a.frame(*options.frame);  // throws CaptureError naming the frames it has
    b.frame(*options.frame);
  }
  auto wanted = [&](const FrameRecord& f) { return !options.frame || f.index == *options.frame; };
  for (const FrameRecord& fa : a.manifest().frames) {
    if (!wanted(fa)) continue;
    const FrameRecord* fb = nullptr;
    for (const FrameRecord& f : b.manifest().frames)
      if (f.index == fa.index) fb = &f;
    if (!fb) {
      diff.notes.push_back("frame " + std::to_string(fa.index) + only_in_a);
      diff.identical = false;
      diff.beyond_tolerance = true;
      continue;
    }
    FrameDiff frame;
    frame.index = fa.index;
    for (const PassRecord& pa : fa.passes) {
      const PassRecord* pb = find(*fb, pa.name);
      if (!pb) {
        frame.passes.push_back({pa.name, PassStatus::only_in_a, false, false, false, {}, true});
        continue;
      }
      frame.passes.push_back(diff_pass(a, fa, pa, b, *pb, options));
    }
    for (const PassRecord& pb : fb->passes)
      if (!find(fa, pb.name)) frame.passes.push_back({pb.name, PassStatus::only_in_b, false, false, false, {}, true});
    for (const PassDiff& p : frame.passes) {
      if (p.status != PassStatus::identical && p.status != PassStatus::skipped) diff.identical = false;
      diff.beyond_tolerance |= p.beyond_tolerance;
      if (!diff.first_divergence && (p.status == PassStatus::origin || p.status == PassStatus::skipped_in_a ||
                                     p.status == PassStatus::skipped_in_b || p.status == PassStatus::only_in_a ||
                                     p.status == PassStatus::only_in_b))
        diff.first_divergence = {frame.index, p.name};
    }
    diff.frames.push_back(std::move(frame));
  }
  for (const FrameRecord& fb : b.manifest().frames) {
    if (!wanted(fb)) continue;
    bool found = false;
    for (const FrameRecord& fa : a.manifest().frames) found |= fa.index == fb.index;
    if (!found) {
      diff.notes.push_back("frame " + std::to_string(fb.index) + only_in_b);
      diff.identical = false;
      diff.beyond_tolerance = true;
    }
  }
  return diff;
}

void print_diff_table(std::ostream& out, const CaptureDiff& diff) {
  for (const FrameDiff& frame : diff.frames) {
    out << "frame " << frame.index << "\n";
    out << std::left << std::setw(22) << "  pass" << std::setw(22) << "resource" << std::setw(11) << "status"
        << std::right << std::setw(11) << "max abs" << std::setw(11) << "RMSE" << std::setw(9) << "PSNR" << std::setw(8)
        << ">thr %" << std::setw(12) << "NaN/Inf"
        << "\n";
    for (const PassDiff& p : frame.passes) {
      if (p.outputs.empty() || (p.status != PassStatus::origin && p.status != PassStatus::inherited)) {
        out << "  " << std::left << std::setw(20) << p.name << std::setw(22) << "" << status_name(p.status, diff.golden)
            << "\n";
        continue;
      }
      for (const OutputDiff& o : p.outputs) {
        const ResourceComparison& c = o.comparison;
        out << "  " << std::left << std::setw(20) << p.name << std::setw(22) << o.resource << std::setw(11)
            << (c.identical ? "identical" : status_name(p.status, diff.golden));
        if (!c.identical && c.comparable)
          out << std::right << std::setw(11) << number(c.max_abs) << std::setw(11) << number(c.rmse) << std::setw(9)
              << number(c.psnr, 3) << std::setw(8) << number(100.0 * c.over_threshold_share, 3) << std::setw(12)
              << (std::to_string(c.nan_b) + "/" + std::to_string(c.inf_b));
        else if (!c.comparable)
          out << "  " << c.note;
        if (!o.held_to.empty()) out << "  held to " << o.held_to << (o.beyond ? ": beyond" : ": met");
        if (o.threshold && !o.comparison.identical)
          out << (o.threshold->problem.empty()
                      ? " (" + std::to_string(o.threshold->over) + " of " + std::to_string(o.threshold->counted) +
                            " texels over, worst " + number(o.threshold->worst) + ")"
                      : " (" + o.threshold->problem + ")");
        if (o.flip) out << "  FLIP mean " << number(o.flip->mean) << " max " << number(o.flip->max);
        if (!c.first_difference.empty()) out << "  first at " << c.first_difference;
        out << "\n";
      }
    }
  }
  for (const std::string& note : diff.notes) out << "note: " << note << "\n";
  if (diff.first_divergence)
    out << "first divergence: " << diff.first_divergence->second << " (frame " << diff.first_divergence->first << ")\n";
  else
    out << (diff.identical ? "no differences\n" : "differences, but no pass where they start with equal inputs\n");
}

nlohmann::json diff_to_json(const CaptureDiff& diff) {
  nlohmann::json frames = nlohmann::json::array();
  for (const FrameDiff& frame : diff.frames) {
    nlohmann::json passes = nlohmann::json::array();
    for (const PassDiff& p : frame.passes) {
      nlohmann::json outputs = nlohmann::json::array();
      for (const OutputDiff& o : p.outputs) {
        const ResourceComparison& c = o.comparison;
        nlohmann::json j = {{"resource", o.resource},
                            {"identical", c.identical},
                            {"comparable", c.comparable},
                            {"metric", c.metric},
                            {"max_abs", finite_or_null(c.max_abs)},
                            {"rmse", finite_or_null(c.rmse)},
                            {"psnr", finite_or_null(c.psnr)},
                            {"over_threshold_share", c.over_threshold_share},
                            {"differing", c.differing},
                            {"nan_a", c.nan_a},
                            {"nan_b", c.nan_b},
                            {"inf_a", c.inf_a},
                            {"inf_b", c.inf_b}};
        if (c.metric == "angle") {
          j["angular_max_deg"] = c.angular_max_deg;
          j["angular_mean_deg"] = c.angular_mean_deg;
        }
        if (o.flip)
          j["flip"] = {{"mean", o.flip->mean}, {"max", o.flip->max}, {"median", o.flip->median},
                       {"p95", o.flip->p95},   {"p99", o.flip->p99}, {"over_0.1", o.flip->over_threshold_share}};
        if (!c.note.empty()) j["note"] = c.note;
        if (!o.missing.empty()) j["missing"] = o.missing;
        if (!c.first_difference.empty()) j["first_difference"] = c.first_difference;
        if (!o.held_to.empty()) {
          j["held_to"] = o.held_to;
          j["beyond"] = o.beyond;
          if (!o.contract.measure.empty())
            j["contract"] = {{"worst", finite_or_null(o.contract.worst)},
                             {"bound", o.contract.bound},
                             {"measure", o.contract.measure}};
          if (o.threshold) {
            j["threshold"] = {{"counted", o.threshold->counted},
                              {"over", o.threshold->over},
                              {"worst", finite_or_null(o.threshold->worst)}};
            if (!o.threshold->problem.empty()) j["threshold"]["problem"] = o.threshold->problem;
          }
        }
        outputs.push_back(j);
      }
      passes.push_back({{"name", p.name},
                        {"status", status_name(p.status, diff.golden)},
                        {"inputs_agree", p.inputs_agree},
                        {"params_agree", p.params_agree},
                        {"shaders_agree", p.shaders_agree},
                        {"beyond_tolerance", p.beyond_tolerance},
                        {"outputs", outputs}});
    }
    frames.push_back({{"index", frame.index}, {"passes", passes}});
  }
  nlohmann::json first = nullptr;
  if (diff.first_divergence) first = {{"frame", diff.first_divergence->first}, {"pass", diff.first_divergence->second}};
  return {{"identical", diff.identical},
          {"beyond_tolerance", diff.beyond_tolerance},
          {"first_divergence", first},
          {"notes", diff.notes},
          {"frames", frames}};
}

}  // namespace nightcap
