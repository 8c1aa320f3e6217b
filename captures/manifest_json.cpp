// The manifest as JSON, both ways: what CaptureWriter writes, and the reader that refuses any
// manifest it would not have written (a field of the wrong type or out of range, a name or blob
// path that could leave the capture), naming the file and the field.
#include <algorithm>
#include <set>

#include "captures/capture.h"
#include "passes/core/hash.h"

namespace nightcap {
using nlohmann::json;

namespace {

constexpr uint64_t kMaxResourceBytes = uint64_t(4) << 30;

[[noreturn]] void fail(const std::string& file, const std::string& where, const std::string& problem) {
  throw CaptureError(file + ": " + (where.empty() ? "" : where + ": ") + problem);
}

// A blob path stays inside the capture: blobs/<hash>.<ext>, nothing else.
bool safe_blob_path(const std::string& blob, const std::string& hash) {
  if (blob.rfind("blobs/", 0) != 0 || blob.size() > 128) return false;
  for (char c : blob)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-' || c == '/')) return false;
  const std::string name = blob.substr(6);
  if (name.find('/') != std::string::npos || name.find("..") != std::string::npos) return false;
  return name.rfind(hash + ".", 0) == 0;
}

// The member, or null when absent (or `object` is not an object), without copying it: the
// frames array is most of the manifest.
const json& member(const json& object, const char* key) {
  static const json null;
  const auto found = object.find(key);
  return found == object.end() ? null : *found;
}

template <typename T>
T field(const json& object, const char* key, const std::string& file, const std::string& where) {
  if (!object.is_object() || !object.contains(key)) fail(file, where, std::string("missing \"") + key + "\"");
  try {
    return object.at(key).get<T>();
  } catch (const json::exception&) {
    fail(file, where, std::string("\"") + key + "\" has the wrong type");
  }
}

uint32_t bounded(const json& object, const char* key, uint32_t max, const std::string& file, const std::string& where) {
  const json& value = member(object, key);
  if (!value.is_number_integer()) fail(file, where, std::string("\"") + key + "\" must be an integer");
  const int64_t v = value.get<int64_t>();
  if (v < 1 || v > int64_t(max))
    fail(file, where, std::string(key) + " " + std::to_string(v) + " outside 1.." + std::to_string(max));
  return uint32_t(v);
}

ResourceRecord resource_from_json(const json& j, const std::string& file, const std::string& where) {
  ResourceRecord r;
  r.resource = field<std::string>(j, "resource", file, where);
  if (!safe_name(r.resource)) fail(file, where, "bad resource name");
  const std::string kind = field<std::string>(j, "kind", file, where);
  auto k = kind_by_name(kind);
  if (!k) fail(file, where, "unknown kind '" + kind + "'");
  r.kind = *k;
  const std::string format = field<std::string>(j, "format", file, where);
  r.hash = field<std::string>(j, "hash", file, where);
  r.blob = field<std::string>(j, "blob", file, where);
  if (!is_content_hash(r.hash)) fail(file, where, "hash '" + r.hash + "' is not a content hash");
  if (!safe_blob_path(r.blob, r.hash))
    fail(file, where, "blob path '" + r.blob + "' leaves blobs/ or does not match its hash");
  const uint64_t bytes = [&] {
    const json& b = member(j, "bytes");
    if (!b.is_number_unsigned() && !b.is_number_integer()) fail(file, where, "\"bytes\" must be an integer");
    if (b.is_number_integer() && b.get<int64_t>() < 0) fail(file, where, "\"bytes\" is negative");
    return b.get<uint64_t>();
  }();
  if (format == "BUFFER") {
    r.is_buffer = true;
    if (bytes > kMaxResourceBytes) fail(file, where, "buffer of " + std::to_string(bytes) + " bytes is too large");
    r.buffer_size = bytes;
    return r;
  }
  auto info = format_by_name(format);
  if (!info) fail(file, where, "unknown format '" + format + "'");
  r.is_buffer = false;
  r.format = info->vk;
  r.extent.width = bounded(j, "width", kMaxImageSide, file, where);
  r.extent.height = bounded(j, "height", kMaxImageSide, file, where);
  r.extent.depth = j.contains("depth") ? bounded(j, "depth", 4096, file, where) : 1;
  r.extent.layers = bounded(j, "layers", 2048, file, where);
  const uint32_t max_mips = uint32_t(std::bit_width(std::max({r.extent.width, r.extent.height, r.extent.depth})));
  r.extent.mips = bounded(j, "mips", max_mips, file, where);
  uint64_t texels = 0;
  if (__builtin_mul_overflow(uint64_t(r.extent.width), uint64_t(r.extent.height), &texels) ||
      __builtin_mul_overflow(texels, uint64_t(r.extent.depth), &texels) ||
      __builtin_mul_overflow(texels, uint64_t(r.extent.layers), &texels) ||
      __builtin_mul_overflow(texels, uint64_t(info->texel_bytes + (info->has_stencil ? 1 : 0)), &texels) ||
      texels > kMaxResourceBytes)
    fail(file, where,
         "image of " + std::to_string(r.extent.width) + "x" + std::to_string(r.extent.height) + "x" +
             std::to_string(r.extent.layers) + " is too large");
  if (bytes != r.raw_bytes()) fail(file, where, "\"bytes\" " + std::to_string(bytes) + " does not match the size");
  if (j.contains("cube")) {
    if (!j.at("cube").is_boolean()) fail(file, where, "\"cube\" is not true or false");
    r.cube = j.at("cube").get<bool>();
    if (r.cube && (r.extent.width != r.extent.height || r.extent.layers % 6 != 0))
      fail(file, where, "a cube needs square faces and a multiple of 6 layers");
  }
  return r;
}

ComparisonContract contract_from_json(const json& output, const std::string& file, const std::string& where) {
  const json& c = member(output, "contract");
  ComparisonContract contract;
  const std::string kind = field<std::string>(c, "kind", file, where + ".contract");
  if (!contract_kind_by_name(kind, contract.kind)) fail(file, where, "unknown contract kind '" + kind + "'");
  contract.absolute = field<double>(c, "absolute", file, where + ".contract");
  contract.relative = field<double>(c, "relative", file, where + ".contract");
  if (!(contract.absolute >= 0) || !(contract.relative >= 0)) fail(file, where, "contract bounds must be >= 0");
  contract.order_dependent = field<bool>(c, "order_dependent", file, where + ".contract");
  contract.reason = field<std::string>(c, "reason", file, where + ".contract");
  return contract;
}

// Optional: captures from before schemas were declared compare their buffers as words.
std::optional<BufferSchema> output_schema(const json& output, const ResourceRecord& record, const std::string& file,
                                          const std::string& where) {
  if (!output.contains("schema")) return std::nullopt;
  if (!record.is_buffer) fail(file, where, "an image has no buffer schema");
  try {
    return schema_from_json(output.at("schema"));
  } catch (const std::invalid_argument& e) {
    fail(file, where + ".schema", e.what());
  }
}

// Optional: only a pass rendered with `--inject-nan` has one, naming a float image output of the
// pass and a texel of its mip 0.
InjectedNanRecord injected_nan_from_json(const json& j, const PassRecord& pass, const std::string& file,
                                         const std::string& where) {
  if (!pass.ran) fail(file, where, "a skipped pass has no NaN injection");
  InjectedNanRecord nan;
  nan.resource = field<std::string>(j, "resource", file, where);
  const auto out = std::find_if(pass.outputs.begin(), pass.outputs.end(),
                                [&](const ResourceRecord& r) { return r.resource == nan.resource; });
  if (out == pass.outputs.end() || out->is_buffer || !is_float_colour(*format_info(out->format)))
    fail(file, where, "'" + nan.resource + "' is not a float image output of the pass");
  auto coordinate = [&](const char* key, uint32_t extent) {
    const json& value = member(j, key);
    if (!value.is_number_integer() || value.get<int64_t>() < 0 || value.get<int64_t>() >= int64_t(extent))
      fail(file, where, std::string("\"") + key + "\" must be an integer in 0.." + std::to_string(extent - 1));
    return value.get<uint32_t>();
  };
  nan.x = coordinate("x", out->extent.width);
  nan.y = coordinate("y", out->extent.height);
  return nan;
}

}  // namespace

bool safe_name(const std::string& name) {
  if (name.empty() || name.size() > 256 || name == "." || name == "..") return false;
  for (char c : name)
    if (c < 0x21 || c > 0x7e || c == '/' || c == '\\') return false;
  return true;
}

json to_json(const ResourceRecord& r) {
  json j = {{"resource", r.resource}, {"kind", r.kind.name()}};
  if (r.is_buffer) {
    j["format"] = "BUFFER";
    j["width"] = r.buffer_size;
    j["height"] = j["depth"] = j["mips"] = j["layers"] = 1;
  } else {
    j["format"] = format_info(r.format)->name;
    j["width"] = r.extent.width;
    j["height"] = r.extent.height;
    j["depth"] = r.extent.depth;
    j["mips"] = r.extent.mips;
    j["layers"] = r.extent.layers;
    if (r.cube) j["cube"] = true;  // absent: not a cube
  }
  j["bytes"] = r.raw_bytes();
  j["hash"] = r.hash;
  j["blob"] = r.blob;
  return j;
}

namespace {

// A parameter's declaration as the manifest's "param_types" records it.
json to_json(const ParamDecl& p) {
  json j = {{"type", type_name(p.type)}};
  if (p.type == ParamType::real || p.type == ParamType::integer) {
    j["min"] = p.min;
    j["max"] = p.max;
  }
  if (p.type == ParamType::choice) {
    j["choices"] = json::array();
    for (const ParamChoice& c : p.choices) j["choices"].push_back({{"name", c.name}, {"value", c.value}});
  }
  if (!p.group.empty()) j["group"] = p.group;
  return j;
}

ParamDecl param_type_from_json(const std::string& name, const json& j) {
  ParamDecl p;
  p.name = name;
  const std::string type = j.at("type").get<std::string>();
  for (ParamType t : {ParamType::real, ParamType::integer, ParamType::boolean, ParamType::choice})
    if (type == type_name(t)) p.type = t;
  if (type != type_name(p.type)) throw std::runtime_error("unknown parameter type '" + type + "'");
  p.min = j.value("min", 0.0);
  p.max = j.value("max", p.type == ParamType::boolean ? 1.0 : 0.0);
  for (const json& c : j.value("choices", json::array()))
    p.choices.push_back({c.at("name").get<std::string>(), c.at("value").get<double>()});
  p.group = j.value("group", "");
  return p;
}

}  // namespace

json to_json(const CaptureManifest& m) {
  json frames = json::array();
  for (const FrameRecord& f : m.frames) {
    json passes = json::array();
    for (const PassRecord& p : f.passes) {
      json pass = {{"name", p.name}, {"status", p.ran ? "ran" : "skipped"}};
      if (!p.stage.empty()) pass["stage"] = p.stage;
      if (!p.ran) pass["reason"] = p.reason;
      pass["gpu_ms"] = p.gpu_ms ? json(*p.gpu_ms) : json(nullptr);
      pass["cpu_ms"] = p.cpu_ms;
      pass["time_ms"] = p.time_ms;
      pass["clock"] = pass_clock_name(p.clock);
      if (p.gpu_ms) pass["record_ms"] = p.record_ms;
      pass["params"] = p.params;
      if (!p.param_types.empty()) {
        json types = json::object();
        for (const ParamDecl& param : p.param_types) types[param.name] = to_json(param);
        pass["param_types"] = types;
      }
      json shaders = json::array(), inputs = json::array(), outputs = json::array();
      for (const ShaderRecord& s : p.shaders)
        shaders.push_back({{"path", s.path},
                           {"hash", s.hash},
                           {"blob", s.blob},
                           {"source_hash", s.source_hash},
                           {"source_blob", s.source_blob}});
      for (const ResourceRecord& r : p.inputs) inputs.push_back(to_json(r));
      for (const ResourceRecord& r : p.outputs) {
        json out = to_json(r);
        out["contract"] = {{"kind", contract_kind_name(r.contract.kind)},
                           {"absolute", r.contract.absolute},
                           {"relative", r.contract.relative},
                           {"order_dependent", r.contract.order_dependent},
                           {"reason", r.contract.reason}};
        if (r.schema) out["schema"] = to_json(*r.schema);
        outputs.push_back(out);
      }
      pass["shaders"] = shaders;
      pass["pipelines"] = p.pipelines;
      pass["samplers"] = p.samplers;
      pass["inputs"] = inputs;
      pass["outputs"] = outputs;
      if (p.injected_nan)
        pass["injected_nan"] = {
            {"resource", p.injected_nan->resource}, {"x", p.injected_nan->x}, {"y", p.injected_nan->y}};
      passes.push_back(pass);
    }
    frames.push_back({{"index", f.index},
                      {"output", {{"width", f.width}, {"height", f.height}}},
                      {"sinks", f.sinks},
                      {"time", f.time},
                      {"wall_ms", f.wall_ms ? json(*f.wall_ms) : json(nullptr)},
                      {"camera_cut", f.camera_cut},
                      {"history_reset", f.history_reset},
                      {"camera",
                       {{"view", f.camera.view},
                        {"projection", f.camera.projection},
                        {"position", f.camera.position},
                        {"yfov", f.camera.yfov},
                        {"znear", f.camera.znear},
                        {"depth_convention", f.camera.depth_convention}}},
                      {"passes", passes}});
  }
  json j = {{"format", "nightcap-capture"}, {"version", m.version}, {"device", m.device},
            {"settings", m.settings},       {"scene", m.scene},     {"frames", frames}};
  if (m.blobs_in_store) j["blobs"] = "store";  // absent: in the capture folder
  if (!m.golden.is_null()) j["golden"] = m.golden;
  return j;
}

CaptureManifest manifest_from_json(const json& j, const std::string& file) {
  CaptureManifest m;
  if (!j.is_object()) fail(file, "", "not a JSON object");
  if (!j.contains("format") || j.at("format") != "nightcap-capture")
    fail(file, "", "not a nightcap capture (\"format\")");
  if (!j.contains("version") || !j.at("version").is_number_integer()) fail(file, "", "missing integer \"version\"");
  m.version = j.at("version").get<int>();
  if (m.version < 1) fail(file, "", "bad version " + std::to_string(m.version));
  if (m.version < kCaptureVersion)
    fail(file, "",
         "capture version " + std::to_string(m.version) + " is no longer read (this nightcap reads version " +
             std::to_string(kCaptureVersion) + "): render it again");
  if (m.version > kCaptureVersion)
    fail(file, "",
         "capture version " + std::to_string(m.version) + " is newer than this nightcap reads (" +
             std::to_string(kCaptureVersion) + ")");
  m.device = j.value("device", json::object());
  m.settings = j.value("settings", json::object());
  m.scene = j.value("scene", json::object());
  if (!m.settings.is_object()) fail(file, "settings", "not an object");
  for (const char* key : {"width", "height"})
    if (m.settings.contains(key)) {
      const json& v = m.settings.at(key);
      if (!v.is_number_integer() || v.get<int64_t>() < 1 || v.get<int64_t>() > kMaxImageSide)
        fail(file, std::string("settings.") + key, "outside 1.." + std::to_string(kMaxImageSide));
    }
  if (j.contains("blobs")) {
    if (j.at("blobs") != "store") fail(file, "", "\"blobs\" must be \"store\" when present");
    m.blobs_in_store = true;
  }
  if (j.contains("golden")) {
    m.golden = j.at("golden");
    for (const char* key : {"source", "updated"})
      if (!m.golden.is_object() || !member(m.golden, key).is_string())
        fail(file, "golden", std::string("missing string \"") + key + "\"");
  }
  const json& frames = member(j, "frames");
  if (!frames.is_array()) fail(file, "", "missing \"frames\" array");
  // The tools align frames by index, passes by name and versions by resource name: a name that
  // repeats would pair records that are not the same thing.
  std::set<uint32_t> frame_indices;
  for (size_t fi = 0; fi < frames.size(); ++fi) {
    const std::string fw = "frames[" + std::to_string(fi) + "]";
    FrameRecord f;
    f.index = field<uint32_t>(frames[fi], "index", file, fw);
    if (!frame_indices.insert(f.index).second) fail(file, fw, "frame " + std::to_string(f.index) + " appears twice");
    const json& output = member(frames[fi], "output");
    f.width = bounded(output, "width", kMaxImageSide, file, fw + ".output");
    f.height = bounded(output, "height", kMaxImageSide, file, fw + ".output");
    f.sinks = field<std::vector<std::string>>(frames[fi], "sinks", file, fw);
    for (const std::string& sink : f.sinks)
      if (!safe_name(sink)) fail(file, fw, "bad sink name");
    f.time = field<double>(frames[fi], "time", file, fw);
    if (frames[fi].contains("wall_ms") && !frames[fi].at("wall_ms").is_null())
      f.wall_ms = field<double>(frames[fi], "wall_ms", file, fw);
    f.camera_cut = field<bool>(frames[fi], "camera_cut", file, fw);
    f.history_reset = field<std::map<std::string, std::string>>(frames[fi], "history_reset", file, fw);
    for (const auto& [resource, reason] : f.history_reset)
      if (!safe_name(resource)) fail(file, fw + ".history_reset", "bad resource name");
    if (frames[fi].contains("camera")) {
      const json& c = frames[fi].at("camera");
      try {
        f.camera.view = c.at("view").get<std::array<double, 16>>();
        f.camera.projection = c.at("projection").get<std::array<double, 16>>();
        f.camera.position = c.at("position").get<std::array<double, 3>>();
        f.camera.yfov = c.at("yfov").get<double>();
        f.camera.znear = c.at("znear").get<double>();
        f.camera.depth_convention = c.at("depth_convention").get<std::string>();
      } catch (const json::exception& e) {
        fail(file, fw + ".camera", e.what());
      }
    }
    const json& passes = member(frames[fi], "passes");
    if (!passes.is_array()) fail(file, fw, "missing \"passes\" array");
    std::set<std::string> pass_names;
    for (size_t pi = 0; pi < passes.size(); ++pi) {
      const std::string pw = fw + ".passes[" + std::to_string(pi) + "]";
      const json& pj = passes[pi];
      PassRecord p;
      p.name = field<std::string>(pj, "name", file, pw);
      if (!safe_name(p.name)) fail(file, pw, "bad pass name");
      if (!pass_names.insert(p.name).second) fail(file, pw, "pass '" + p.name + "' appears twice in the frame");
      const std::string status = field<std::string>(pj, "status", file, pw);
      if (status != "ran" && status != "skipped") fail(file, pw, "status must be ran or skipped");
      p.ran = status == "ran";
      p.reason = pj.value("reason", "");
      if (pj.contains("stage")) {
        p.stage = field<std::string>(pj, "stage", file, pw);
        if (!safe_name(p.stage)) fail(file, pw, "bad stage name");
      }
      if (pj.contains("gpu_ms") && !pj.at("gpu_ms").is_null()) p.gpu_ms = field<double>(pj, "gpu_ms", file, pw);
      p.cpu_ms = pj.value("cpu_ms", 0.0);
      // Captures made before pass times had a clock were timed by the device's timestamps.
      p.clock = p.gpu_ms ? PassClock::device : PassClock::host;
      p.time_ms = p.gpu_ms.value_or(p.cpu_ms);
      if (pj.contains("clock")) {
        const auto clock = pass_clock_from_name(field<std::string>(pj, "clock", file, pw));
        if (!clock) fail(file, pw, "\"clock\" must be device, host-alone or host");
        p.clock = *clock;
        p.time_ms = field<double>(pj, "time_ms", file, pw);
      }
      if (pj.contains("record_ms")) p.record_ms = field<double>(pj, "record_ms", file, pw);
      try {
        p.params = pj.value("params", json::object()).get<std::map<std::string, double>>();
      } catch (const json::exception&) {
        fail(file, pw, "\"params\" must map names to numbers");
      }
      try {
        const json types = pj.value("param_types", json::object());
        for (const auto& [name, type] : types.items()) p.param_types.push_back(param_type_from_json(name, type));
      } catch (const std::exception& e) {
        fail(file, pw, std::string("\"param_types\": ") + e.what());
      }
      for (const char* state : {"pipelines", "samplers"})
        if (!pj.contains(state) || !pj.at(state).is_array())
          fail(file, pw, std::string("missing \"") + state + "\" array");
      p.pipelines = pj.at("pipelines");
      p.samplers = pj.at("samplers");
      for (const json& s : pj.value("shaders", json::array())) {
        ShaderRecord shader{field<std::string>(s, "path", file, pw), field<std::string>(s, "hash", file, pw),
                            field<std::string>(s, "blob", file, pw), field<std::string>(s, "source_hash", file, pw),
                            field<std::string>(s, "source_blob", file, pw)};
        if (!is_content_hash(shader.hash) || !safe_blob_path(shader.blob, shader.hash))
          fail(file, pw, "bad shader blob '" + shader.blob + "'");
        if (!is_content_hash(shader.source_hash) || !safe_blob_path(shader.source_blob, shader.source_hash))
          fail(file, pw, "bad shader source blob '" + shader.source_blob + "'");
        p.shaders.push_back(shader);
      }
      for (const char* side : {"inputs", "outputs"}) {
        const json& list = member(pj, side);
        if (!list.is_array()) fail(file, pw, std::string("missing \"") + side + "\" array");
        std::set<std::string> resources;
        for (size_t ri = 0; ri < list.size(); ++ri) {
          const std::string rw = pw + "." + side + "[" + std::to_string(ri) + "]";
          ResourceRecord r = resource_from_json(list[ri], file, rw);
          if (!resources.insert(r.resource).second)
            fail(file, rw, "resource '" + r.resource + "' appears twice among the " + side);
          if (std::string(side) == "outputs") {
            r.contract = contract_from_json(list[ri], file, rw);
            r.schema = output_schema(list[ri], r, file, rw);
          }
          (std::string(side) == "inputs" ? p.inputs : p.outputs).push_back(std::move(r));
        }
      }
      if (pj.contains("injected_nan"))
        p.injected_nan = injected_nan_from_json(pj.at("injected_nan"), p, file, pw + ".injected_nan");
      f.passes.push_back(std::move(p));
    }
    m.frames.push_back(std::move(f));
  }
  return m;
}

}  // namespace nightcap
