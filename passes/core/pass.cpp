#include "passes/core/pass.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <stdexcept>

namespace nightcap {

uint64_t ResourceDesc::raw_bytes() const {
  if (is_buffer) return buffer_size;
  return raw_image_bytes(*format_info(format), extent);
}

std::string ResourceUse::shader_name() const {
  if (!role.empty()) return role;
  std::string name = resource;
  if (prefix && !name.empty() && name.back() == '.') name.pop_back();
  std::replace(name.begin(), name.end(), '.', '_');
  return history ? name + "_previous" : name;
}

PassDecl& PassDecl::read(std::string resource, Use use) {
  ResourceUse u;
  u.resource = std::move(resource);
  u.use = use;
  inputs.push_back(std::move(u));
  last_use_is_output_ = false;
  return *this;
}

PassDecl& PassDecl::read_all(std::string prefix, Use use) {
  read(std::move(prefix), use);
  inputs.back().prefix = true;
  return *this;
}

PassDecl& PassDecl::write(std::string resource, Use use, ImageDecl decl) {
  ResourceUse u;
  u.resource = std::move(resource);
  u.use = use;
  u.image = decl;
  outputs.push_back(std::move(u));
  last_use_is_output_ = true;
  return *this;
}

PassDecl& PassDecl::write(std::string resource, Use use, BufferDecl decl) {
  ResourceUse u;
  u.resource = std::move(resource);
  u.use = use;
  u.is_buffer = true;
  u.buffer = decl;
  outputs.push_back(std::move(u));
  last_use_is_output_ = true;
  return *this;
}

PassDecl& PassDecl::modify(std::string resource, Use use) {
  ResourceUse u;
  u.resource = std::move(resource);
  u.use = use;
  u.modifies = true;
  outputs.push_back(std::move(u));
  last_use_is_output_ = true;
  return *this;
}

PassDecl& PassDecl::read(std::string resource, Use use, Subresources range) {
  read(std::move(resource), use);
  inputs.back().range = range;
  return *this;
}

PassDecl& PassDecl::write(std::string resource, Use use, ImageDecl decl, Subresources range) {
  write(std::move(resource), use, decl);
  outputs.back().range = range;
  return *this;
}

PassDecl& PassDecl::modify(std::string resource, Use use, Subresources range) {
  modify(std::move(resource), use);
  outputs.back().range = range;
  return *this;
}

PassDecl& PassDecl::read_optional(std::string resource, Use use) {
  read(std::move(resource), use);
  inputs.back().optional = true;
  return *this;
}

PassDecl& PassDecl::read_previous(std::string resource, Use use) {
  read(std::move(resource), use);
  inputs.back().history = true;
  return *this;
}

PassDecl& PassDecl::as(std::string role) {
  std::vector<ResourceUse>& uses = last_use_is_output_ ? outputs : inputs;
  if (uses.empty()) throw std::logic_error(name + ": as('" + role + "') follows no read or write");
  const bool identifier = !role.empty() && !std::isdigit(static_cast<unsigned char>(role[0])) &&
                          std::all_of(role.begin(), role.end(),
                                      [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
  if (!identifier) throw std::logic_error(name + ": as('" + role + "') is not a GLSL identifier");
  uses.back().role = std::move(role);
  return *this;
}

PassDecl& PassDecl::can_disable(std::string reason, std::string group) {
  disabled_reason = std::move(reason);
  ParamDecl enabled = ParamDecl::boolean("enabled", true, "0 skips the pass (" + disabled_reason + ")");
  return param(group.empty() || group == name ? std::move(enabled) : std::move(enabled).shared_by(std::move(group)));
}

PassDecl& PassDecl::param(ParamDecl decl) {
  if (find_param(decl.name)) throw std::logic_error(name + ": parameter '" + decl.name + "' declared twice");
  params.push_back(std::move(decl));
  return *this;
}

PassDecl& PassDecl::param_float(std::string param_name, double default_value, double min, double max,
                                std::string help) {
  return param(ParamDecl::real(std::move(param_name), default_value, min, max, std::move(help)));
}

PassDecl& PassDecl::param_int(std::string param_name, double default_value, double min, double max, std::string help) {
  return param(ParamDecl::integer(std::move(param_name), default_value, min, max, std::move(help)));
}

PassDecl& PassDecl::flag(std::string param_name, bool default_value, std::string help) {
  return param(ParamDecl::boolean(std::move(param_name), default_value, std::move(help)));
}

PassDecl& PassDecl::choice(std::string param_name, double default_value, std::vector<ParamChoice> choices,
                           std::string help) {
  return param(ParamDecl::choice(std::move(param_name), default_value, std::move(choices), std::move(help)));
}

PassDecl& PassDecl::needs(std::string feature) {
  features.push_back(std::move(feature));
  return *this;
}

PassDecl& PassDecl::shader(std::string path) {
  shaders.push_back(std::move(path));
  return *this;
}

PassDecl& PassDecl::slots(const std::string& resource, uint32_t count) {
  for (std::vector<ResourceUse>* uses : {&inputs, &outputs})
    for (ResourceUse& use : *uses)
      if (use.resource == resource) {
        use.slots = count;
        return *this;
      }
  throw std::logic_error(name + ": slots() names '" + resource + "', which it does not use");
}

namespace {

ResourceUse& sampled_input(PassDecl& decl, const std::string& resource, const char* call) {
  for (ResourceUse& use : decl.inputs)
    if (use.resource == resource && use.use == Use::sampled) return use;
  throw std::logic_error(decl.name + ": " + call + "() names '" + resource + "', which it does not sample");
}

}  // namespace

PassDecl& PassDecl::sampler(const std::string& resource, SamplerDesc desc) {
  sampled_input(*this, resource, "sampler").sampler = desc;
  return *this;
}

PassDecl& PassDecl::aspects(const std::string& resource, std::vector<ViewAspect> per_binding) {
  ResourceUse& use = sampled_input(*this, resource, "aspects");
  use.slots = uint32_t(per_binding.size());
  use.aspects = std::move(per_binding);
  return *this;
}

PassDecl& PassDecl::level_mips(const std::string& resource, std::vector<int> offsets) {
  for (std::vector<ResourceUse>* uses : {&inputs, &outputs})
    for (ResourceUse& use : *uses)
      // By the name it binds: an image the pass reads from the previous frame and writes is two.
      if (use.bound_name() == resource &&
          (use.use == Use::sampled || use.use == Use::storage_read || use.use == Use::storage_write)) {
        use.slots = uint32_t(offsets.size());
        use.level_mips = std::move(offsets);
        return *this;
      }
  throw std::logic_error(name + ": level_mips() names '" + resource + "', which it does not bind as an image");
}

PassDecl& PassDecl::raster(RasterState state) {
  raster_state = state;
  return *this;
}

PassDecl& PassDecl::depth_stencil(DepthStencilState state) {
  depth_stencil_state = state;
  return *this;
}

PassDecl& PassDecl::blend(const std::string& output, BlendState state) {
  for (const ResourceUse& out : outputs)
    if (out.resource == output && out.use == Use::color_attachment) {
      blend_states[output] = state;
      return *this;
    }
  throw std::logic_error(name + ": blend() names '" + output + "', which is not one of its colour outputs");
}

PassDecl& PassDecl::run(std::function<void(PassContext&)> function) {
  execute = std::move(function);
  return *this;
}

PassDecl& PassDecl::skip_when(std::function<std::string(const SkipContext&)> condition) {
  skip_if = std::move(condition);
  return *this;
}

PassDecl& PassDecl::skip_when_cleared(std::vector<std::string> inputs, std::function<bool(const ParamValues&)> exact) {
  cleared_skips.push_back({std::move(inputs), std::move(exact)});
  return *this;
}

bool same_value(VkFormat format, const VkClearValue& a, const VkClearValue& b) {
  const std::optional<FormatInfo> info = format_info(format);
  if (info && info->is_depth)
    return std::memcmp(&a.depthStencil.depth, &b.depthStencil.depth, sizeof(float)) == 0 &&
           a.depthStencil.stencil == b.depthStencil.stencil;
  return std::memcmp(&a.color, &b.color, sizeof a.color) == 0;
}

PassDecl& PassDecl::fold_when_uniform(std::vector<std::string> inputs, decltype(UniformFold::outputs) outputs) {
  uniform_folds.push_back({std::move(inputs), std::move(outputs)});
  return *this;
}

std::string PassDecl::UniformFold::reason() const {
  std::string names;
  for (const std::string& r : inputs) names += (names.empty() ? "" : ", ") + r;
  return "inputs uniform (" + names + "): folded";
}

std::string PassDecl::ClearedSkip::reason() const {
  std::string names;
  for (const std::string& r : inputs) names += (names.empty() ? "" : ", ") + r;
  return "inputs all cleared (" + names + ")";
}

const PassDecl::ClearedSkip* PassDecl::cleared_skip(const std::set<std::string>& cleared,
                                                    const ParamValues& params) const {
  for (const ClearedSkip& skip : cleared_skips)
    if (std::all_of(skip.inputs.begin(), skip.inputs.end(), [&](const std::string& r) { return cleared.count(r); }) &&
        (!skip.exact || skip.exact(params)))
      return &skip;
  return nullptr;
}

PassDecl& PassDecl::compare(const std::string& output, ComparisonContract contract) {
  for (ResourceUse& out : outputs)
    if (out.resource == output) {
      out.contract = std::move(contract);
      return *this;
    }
  throw std::logic_error(name + ": compare() names '" + output + "', which it does not write");
}

PassDecl& PassDecl::layout(const std::string& output, BufferSchema schema) {
  for (ResourceUse& out : outputs)
    if (out.resource == output && out.is_buffer) {
      out.buffer.schema = std::move(schema);
      return *this;
    }
  throw std::logic_error(name + ": layout() names '" + output + "', which is not a buffer it writes");
}

PassDecl& PassDecl::warn_from(const std::string& output, std::function<std::string(std::span<const uint8_t>)> check) {
  for (const ResourceUse& out : outputs)
    if (out.resource == output) {
      warnings.push_back({output, std::move(check)});
      return *this;
    }
  throw std::logic_error(name + ": warn_from() names '" + output + "', which it does not write");
}

const BufferSchema* PassDecl::schema_of(const std::string& output) const {
  for (const ResourceUse& out : outputs)
    if (out.resource == output && out.buffer.schema) return &*out.buffer.schema;
  return nullptr;
}

const ComparisonContract& PassDecl::contract_of(const std::string& output) const {
  for (const ResourceUse& out : outputs)
    if (out.resource == output) return out.contract;
  throw std::logic_error(name + ": has no output '" + output + "'");
}

PassDecl& PassDecl::fullscreen(std::string fragment) {
  shader("frame/fullscreen.vert");
  shader(fragment);
  execute = [](PassContext& ctx) { record_fullscreen(ctx, {}); };
  return *this;
}

ParamValues PassDecl::default_params() const { return resolve_params(*this, {}); }

const ParamDecl* PassDecl::find_param(const std::string& param_name) const {
  for (const ParamDecl& p : params)
    if (p.name == param_name) return &p;
  return nullptr;
}

const PassDecl* find_pass(const std::vector<PassDecl>& passes, const std::string& name) {
  for (const PassDecl& p : passes)
    if (p.name == name) return &p;
  return nullptr;
}

}  // namespace nightcap
