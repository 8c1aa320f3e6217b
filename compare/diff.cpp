#include "compare/diff.h"

#include <algorithm>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

#include "compare/parallel.h"
#include "passes/core/history_name.h"

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

// The frame's own inputs by resource, with their hashes: what its passes read and none of them
// writes. Only passes that ran in `other` (the other capture's frame) too count: what a pass run
// by one capture alone reads is that pass's difference, reported as such. History counts only
// with `history_is_own`: otherwise it is what the previous frame of both captures left, and
// differs only where that frame differed.
std::map<std::string, std::string> own_inputs(const FrameRecord& frame, const FrameRecord& other, bool history_is_own) {
  std::set<std::string> written, ran_in_other;
  for (const PassRecord& p : frame.passes)
    for (const ResourceRecord& r : p.outputs) written.insert(r.resource);
  for (const PassRecord& p : other.passes)
    if (p.ran) ran_in_other.insert(p.name);
  std::map<std::string, std::string> inputs;
  for (const PassRecord& p : frame.passes)
    if (p.ran && ran_in_other.count(p.name))
      for (const ResourceRecord& r : p.inputs)
        if (!written.count(r.resource) && (history_is_own || history_source(r.resource).empty()))
          inputs.emplace(r.resource, r.hash);
  return inputs;
}

std::vector<std::string> differing(const std::map<std::string, std::string>& a,
                                   const std::map<std::string, std::string>& b) {
  std::vector<std::string> names;
  for (const auto& [name, hash] : a)
    if (const auto found = b.find(name); found == b.end() || found->second != hash) names.push_back(name);
  for (const auto& [name, hash] : b)
    if (!a.count(name)) names.push_back(name);
  std::sort(names.begin(), names.end());
  return names;
}

// The keys whose values differ; "" when either side is not an object and they differ.
std::vector<std::string> differing_keys(const nlohmann::json& a, const nlohmann::json& b) {
  if (!a.is_object() || !b.is_object()) return a == b ? std::vector<std::string>{} : std::vector<std::string>{""};
  std::set<std::string> keys;
  for (const auto& [key, value] : a.items()) keys.insert(key);
  for (const auto& [key, value] : b.items()) keys.insert(key);
  std::vector<std::string> out;
  for (const std::string& key : keys)
    if (a.value(key, nlohmann::json()) != b.value(key, nlohmann::json())) out.push_back(key);
  return out;
}

const FrameDiff* first_with_inputs_differing(const CaptureDiff& diff) {
  for (const FrameDiff& frame : diff.frames)
    if (!frame.inputs_differ.empty()) return &frame;
  return nullptr;
}

// Outputs `--tolerance` applies to: float colour values (not normals, depth or buffers).
bool float_output(const ResourceRecord& r) {
  if (r.is_buffer || kind_info(r.kind).measure == KindMeasure::unit_vector) return false;
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

PassDiff run_by_one(const std::string& name, PassStatus status) {
  PassDiff d;
  d.name = name;
  d.status = status;
  d.inputs_agree = d.params_agree = d.shaders_agree = false;
  d.beyond_tolerance = true;
  return d;
}

// An output whose versions differ in bytes, to be measured (loaded, compared, held to its
// threshold) apart from the walk over the passes, so that outputs are measured in parallel.
struct PendingOutput {
  OutputDiff* diff;
  const FrameRecord* frame_a;
  const std::string* pass;
  const ResourceRecord *a, *b;
  const ThresholdRule* rule;
  bool by_tolerance;
};

PassDiff diff_pass(const FrameRecord& frame_a, const PassRecord& a, const PassRecord& b, const DiffOptions& options,
                   std::vector<PendingOutput>& pending) {
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
  d.outputs.reserve(a.outputs.size() + b.outputs.size());
  for (const ResourceRecord& ra : a.outputs) {
    OutputDiff& o = d.outputs.emplace_back();
    o.resource = ra.resource;
    const ResourceRecord* rb = nullptr;
    for (const ResourceRecord& r : b.outputs)
      if (r.resource == ra.resource) rb = &r;
    if (!rb) {
      mark_only_in(o, true, options.golden);
      differs = o.beyond = true;
      continue;
    }
    const ThresholdRule* rule = options.thresholds ? options.thresholds->match(a.name, ra) : nullptr;
    const bool by_tolerance = !rule && options.tolerance && float_output(ra);
    o.held_to = rule           ? rule->description() + " (" + rule->source + ")"
                : by_tolerance ? "max abs <= " + number(*options.tolerance) + " (--tolerance)"
                               : contract_description(ra.contract) + " (recorded contract)";
    if (ra.hash == rb->hash) {
      o.comparison.identical = true;
      o.comparison.metric = "bytes";
      continue;
    }
    differs = true;
    pending.push_back({&o, &frame_a, &a.name, &ra, rb, rule, by_tolerance});
  }
  const auto outputs_a = hashes(a.outputs);
  for (const ResourceRecord& rb : b.outputs)
    if (!outputs_a.count(rb.resource)) {
      OutputDiff& o = d.outputs.emplace_back();
      o.resource = rb.resource;
      mark_only_in(o, false, options.golden);
      differs = o.beyond = true;
    }
  // Equal inputs but different outputs: the change entered here (through a parameter, a
  // shader, or the pass's own behaviour); params_agree and shaders_agree say which.
  if (differs) d.status = d.inputs_agree ? PassStatus::origin : PassStatus::inherited;
  return d;
}

// `cores_busy`: the other cores measure other outputs, so this one's decoding and FLIP run on the
// calling thread (splitting them would only add hand-overs).
void measure(const Capture& ca, const Capture& cb, const PendingOutput& p, const DiffOptions& options,
             bool cores_busy) {
  OutputDiff& o = *p.diff;
  const int threads = cores_busy ? 0 : -1;
  const std::vector<uint8_t> raw_a = ca.load(*p.a, threads), raw_b = cb.load(*p.b, threads);
  const ResourcePair pair(*p.a, raw_a, *p.b, raw_b);
  const bool by_contract = !p.rule && !p.by_tolerance;
  if (by_contract) {
    MeasuredResource measured = measure_resource(p.a->contract, pair);
    o.comparison = std::move(measured.comparison);
    o.contract = std::move(measured.contract);
    o.beyond = !o.contract.holds;
  } else {
    o.comparison = compare_resource(pair);
  }
  if (o.comparison.comparable && displayed_colour(*p.a)) {
    FlipOptions flip;
    flip.threads = cores_busy ? 1 : 0;
    o.flip = flip_displayed(pair, flip);
  }
  if (p.rule) {
    o.threshold = o.comparison.comparable
                      ? check_threshold(*p.rule, *p.frame_a, pair,
                                        o.flip ? std::span<const float>(o.flip->error) : std::span<const float>())
                      : ThresholdCheck{false, 0, 0, INFINITY, o.comparison.note};
    o.beyond = !o.threshold->holds;
  } else if (p.by_tolerance) {
    o.beyond = !o.comparison.comparable || !(o.comparison.max_abs <= *options.tolerance);
  }
  if (options.on_measured) options.on_measured(*p.frame_a, *p.pass, o, pair);
}

// Loading, decoding and comparing are independent per output: a worker per core takes the next
// one (compare/parallel.h).
void measure_all(const Capture& ca, const Capture& cb, const std::vector<PendingOutput>& pending,
                 const DiffOptions& options) {
  // Longest first, so that no worker starts a long one while the others run out of work. The
  // cost is guessed from the size, and FLIP makes a displayed image the longest: at 1280x720 its
  // load, comparison and FLIP took 290 ms here, a half-float RGBA image's load and comparison
  // 110 ms for twice the bytes.
  auto cost = [](const PendingOutput& p) { return p.a->raw_bytes() * (displayed_colour(*p.a) ? 6 : 1); };
  std::vector<const PendingOutput*> order;
  for (const PendingOutput& p : pending) order.push_back(&p);
  std::stable_sort(order.begin(), order.end(), [&](auto* x, auto* y) { return cost(*x) > cost(*y); });
  const bool cores_busy = order.size() > 1;
  for_each_on_cores(order.size(), [&](size_t i) { measure(ca, cb, *order[i], options, cores_busy); });
}

nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

std::string comma_separated(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

bool PassIsolation::pass_changed() const {
  return std::any_of(outputs.begin(), outputs.end(), [](const Output& o) { return !o.reproduced; });
}

// One line on what --isolate found for a pass.
std::string isolation_summary(const PassIsolation& isolation) {
  if (!isolation.reason.empty()) return "not isolated: " + isolation.reason;
  if (!isolation.pass_changed())
    return "B's pass on A's inputs reproduces A's outputs: the difference came through its inputs";
  std::string changed;
  for (const PassIsolation::Output& o : isolation.outputs)
    if (!o.reproduced) changed += (changed.empty() ? "" : ", ") + o.resource + " " + o.made;
  return "B's pass on A's inputs does not reproduce A's outputs (" + changed + "): the pass itself changed";
}

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
  std::vector<PendingOutput> pending;
  // Outputs point into diff.frames: each frame's passes are laid out before any is measured.
  diff.frames.reserve(a.manifest().frames.size());
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
    FrameDiff& frame = diff.frames.emplace_back();
    frame.index = fa.index;
    auto has_previous = [&](const Capture& c) {
      return std::any_of(c.manifest().frames.begin(), c.manifest().frames.end(),
                         [&](const FrameRecord& f) { return f.index + 1 == fa.index; });
    };
    const bool history_is_own = fa.index == 0 || !has_previous(a) || !has_previous(b);
    frame.inputs_differ = differing(own_inputs(fa, *fb, history_is_own), own_inputs(*fb, fa, history_is_own));
    if (!frame.inputs_differ.empty()) {
      diff.identical = false;
      diff.beyond_tolerance = true;
    }
    frame.passes.reserve(fa.passes.size() + fb->passes.size());
    for (const PassRecord& pa : fa.passes) {
      const PassRecord* pb = find(*fb, pa.name);
      if (!pb) {
        frame.passes.push_back(run_by_one(pa.name, PassStatus::only_in_a));
        continue;
      }
      frame.passes.push_back(diff_pass(fa, pa, *pb, options, pending));
    }
    for (const PassRecord& pb : fb->passes)
      if (!find(fa, pb.name)) frame.passes.push_back(run_by_one(pb.name, PassStatus::only_in_b));
  }
  measure_all(a, b, pending, options);
  for (FrameDiff& frame : diff.frames)
    for (PassDiff& p : frame.passes) {
      for (const OutputDiff& o : p.outputs) p.beyond_tolerance |= o.beyond;
      if (p.status != PassStatus::identical && p.status != PassStatus::skipped) diff.identical = false;
      diff.beyond_tolerance |= p.beyond_tolerance;
      if (!diff.first_divergence && (p.status == PassStatus::origin || p.status == PassStatus::skipped_in_a ||
                                     p.status == PassStatus::skipped_in_b || p.status == PassStatus::only_in_a ||
                                     p.status == PassStatus::only_in_b))
        diff.first_divergence = {frame.index, p.name};
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
  diff.settings_differ = differing_keys(a.manifest().settings, b.manifest().settings);
  diff.scene_differ = differing_keys(a.manifest().scene, b.manifest().scene);
  return diff;
}

void print_diff_table(std::ostream& out, const CaptureDiff& diff) {
  // The name columns as wide as their longest entry and two spaces.
  size_t pass_width = 6, resource_width = 10;
  for (const FrameDiff& frame : diff.frames)
    for (const PassDiff& p : frame.passes) {
      pass_width = std::max(pass_width, p.name.size() + 2);
      for (const OutputDiff& o : p.outputs) resource_width = std::max(resource_width, o.resource.size() + 2);
    }
  const int pass_column = int(pass_width), resource_column = int(resource_width);
  for (const FrameDiff& frame : diff.frames) {
    out << "frame " << frame.index << "\n";
    if (!frame.inputs_differ.empty())
      out << "  the frame's own inputs differ: " << comma_separated(frame.inputs_differ) << "\n";
    out << "  " << std::left << std::setw(pass_column) << "pass" << std::setw(resource_column) << "resource"
        << std::setw(11) << "status" << std::right << std::setw(11) << "max abs" << std::setw(11) << "RMSE"
        << std::setw(9) << "PSNR" << std::setw(8) << ">thr %" << std::setw(12) << "NaN/Inf"
        << "\n";
    for (const PassDiff& p : frame.passes) {
      if (p.outputs.empty() || (p.status != PassStatus::origin && p.status != PassStatus::inherited)) {
        out << "  " << std::left << std::setw(pass_column) << p.name << std::setw(resource_column) << ""
            << status_name(p.status, diff.golden) << "\n";
        continue;
      }
      for (const OutputDiff& o : p.outputs) {
        const ResourceComparison& c = o.comparison;
        out << "  " << std::left << std::setw(pass_column) << p.name << std::setw(resource_column) << o.resource
            << std::setw(11) << (c.identical ? "identical" : status_name(p.status, diff.golden));
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
        if (!o.flip_map.empty()) out << " (map " << o.flip_map.string() << ")";
        if (!c.first_difference.empty()) out << "  first at " << c.first_difference;
        out << "\n";
      }
      if (p.isolation)
        out << "  " << std::left << std::setw(pass_column) << p.name << isolation_summary(*p.isolation) << "\n";
    }
  }
  for (const std::string& note : diff.notes) out << "note: " << note << "\n";
  if (!diff.settings_differ.empty()) out << "settings differ: " << comma_separated(diff.settings_differ) << "\n";
  if (!diff.scene_differ.empty())
    out << "the scenes' descriptions differ: " << comma_separated(diff.scene_differ) << "\n";
  const FrameDiff* inputs_differ = first_with_inputs_differing(diff);
  if (diff.first_divergence)
    out << "first divergence: " << diff.first_divergence->second << " (frame " << diff.first_divergence->first << ")\n";
  else if (inputs_differ)
    out << "first divergence: the own inputs of frame " << inputs_differ->index << " ("
        << comma_separated(inputs_differ->inputs_differ) << "), before any pass: no pass differs with equal inputs\n";
  else
    out << (diff.identical ? "no differences\n" : "differences, but no pass where they start with equal inputs\n");
}

nlohmann::json diff_to_json(const CaptureDiff& diff) {
  nlohmann::json frames = nlohmann::json::array();
  nlohmann::json changed = nlohmann::json::array();  // passes --isolate found changed themselves
  bool isolated = false;
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
        if (!o.flip_map.empty()) j["flip"]["map"] = o.flip_map.string();
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
      nlohmann::json pass = {{"name", p.name},
                             {"status", status_name(p.status, diff.golden)},
                             {"inputs_agree", p.inputs_agree},
                             {"params_agree", p.params_agree},
                             {"shaders_agree", p.shaders_agree},
                             {"beyond_tolerance", p.beyond_tolerance},
                             {"outputs", outputs}};
      if (p.isolation) {
        isolated = true;
        nlohmann::json made = nlohmann::json::object();
        for (const PassIsolation::Output& o : p.isolation->outputs) made[o.resource] = o.made;
        pass["isolation"] = {{"ran", p.isolation->reason.empty()},
                             {"pass_changed", p.isolation->pass_changed()},
                             {"summary", isolation_summary(*p.isolation)},
                             {"outputs", made}};
        if (p.isolation->pass_changed()) changed.push_back({{"frame", frame.index}, {"pass", p.name}});
      }
      passes.push_back(pass);
    }
    frames.push_back({{"index", frame.index}, {"inputs_differ", frame.inputs_differ}, {"passes", passes}});
  }
  nlohmann::json first = nullptr;
  if (diff.first_divergence) first = {{"frame", diff.first_divergence->first}, {"pass", diff.first_divergence->second}};
  nlohmann::json input_divergence = nullptr;
  if (const FrameDiff* frame = first_with_inputs_differing(diff))
    input_divergence = {{"frame", frame->index}, {"inputs", frame->inputs_differ}};
  nlohmann::json out = {{"identical", diff.identical},
                        {"beyond_tolerance", diff.beyond_tolerance},
                        {"first_divergence", first},
                        {"input_divergence", input_divergence},
                        {"settings_differ", diff.settings_differ},
                        {"scene_differ", diff.scene_differ},
                        {"notes", diff.notes},
                        {"frames", frames}};
  if (isolated) out["changed_passes"] = changed;
  return out;
}

}  // namespace nightcap
