// The inspect session's commands as one object per command run: the session, where its answer
// goes and whether as JSON. Its commands are defined by what they look at, a file each
// (inspect/commands_*.cpp); the words they take are inspect/command_line.h's.
#pragma once

#include <filesystem>
#include <map>
#include <ostream>
#include <span>

#include "inspect/command_line.h"
#include "inspect/command_output.h"
#include "inspect/nan_origin.h"
#include "inspect/pick.h"
#include "inspect/session.h"
#include "inspect/visualise.h"

namespace nightcap::inspect_cli {

class Runner {
 public:
  Runner(InspectSession& session, std::ostream& out, bool json, bool& finished,
         std::map<uint32_t, DrawIdImage>& draw_ids)
      : session_(session), out_(out), json_(json), finished_(finished), draw_ids_(draw_ids) {}

  void run(const CommandSpec& spec, const Arguments& args);

 private:
  void emit(const ojson& j) { out_ << j.dump() << "\n"; }
  ojson where() const;

  // The frame and its passes (commands_frame.cpp).
  void passes(const CommandSpec& spec, const Arguments& args);
  void go(const CommandSpec& spec, const Arguments& args);
  void show_current();
  void frame(const CommandSpec& spec, const Arguments& args);
  void info(const CommandSpec& spec, const Arguments& args);
  void pipeline(const CommandSpec& spec, const Arguments& args);
  void shader(const CommandSpec& spec, const Arguments& args);

  // Pixels: a texel read and decoded, through the frame and under a pick (commands_pixels.cpp).
  // One texel of one version: its hash, the raw channel values, the stored codes and what they mean.
  ojson texel_json(const ResourceRecord& record, const FrameRecord& frame, const TexelAddress& texel);
  ojson reading_json(const ResourceRecord& record, const FrameRecord& frame, uint32_t x, uint32_t y,
                     const Subimage& subimage);
  void print_reading(const ojson& j);
  // An image whose texels index lists (lights.clusters) under a pixel: the texel of its tile, in
  // the depth slice where the kind's linear depth resource (depth.linear) puts the pixel or at
  // --slice, and that texel's list from the kind's buffer (lights.cluster_indices).
  void listed(const ResourceRecord& record, uint32_t x, uint32_t y, Subimage subimage, bool slice_given);
  void cell(const ResourceRecord& record, uint32_t x, uint32_t y, const Subimage& subimage);
  void pixel(const CommandSpec& spec, const Arguments& args);
  void direction(const CommandSpec& spec, const Arguments& args);
  // The resource the positional at `position` names, or the current pass's first output.
  std::string named_or_first_output(const Arguments& args, size_t position);
  void history(const CommandSpec& spec, const Arguments& args);
  void pick_draw(const CommandSpec& spec, const Arguments& args);

  // Buffers, statistics and exports (commands_resources.cpp).
  void buffer(const CommandSpec& spec, const Arguments& args);
  void stats(const CommandSpec& spec, const Arguments& args);
  void export_files(const CommandSpec& spec, const Arguments& args);
  void write_picture(const std::filesystem::path& file, const ResourceRecord& record, std::span<const uint8_t> raw,
                     const Subimage& subimage, VisualAspect aspect);

  // NaN origins and replays (commands_verify.cpp).
  void nan_origin(const CommandSpec& spec, const Arguments& args);
  ojson origin_json(const FrameRecord& frame, const NanOrigin& origin);
  void print_non_finite(const ojson& resource);
  void replay(const CommandSpec& spec, const Arguments& args);

  // Help and quit (commands.cpp).
  void help(const CommandSpec& spec, const Arguments& args);
  void quit(const CommandSpec& spec, const Arguments& args);

  InspectSession& session_;
  std::ostream& out_;
  bool json_;
  bool& finished_;
  std::map<uint32_t, DrawIdImage>& draw_ids_;
};

}  // namespace nightcap::inspect_cli
