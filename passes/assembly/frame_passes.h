// The frame's assembly: which passes make a frame, in stages, and the names of what flows between
// them (passes/assembly/registry.cpp). The only code that names every stage: a pass put between
// two others is wired here, not in its neighbours.
#pragma once

#include <string>
#include <vector>

#include "passes/core/pass.h"

namespace nightcap {

// Which pass lights the frame. Both write lighting.diffuse and lighting.specular, so a frame has
// one: lighting.tiled shades each pixel's froxel list of lights.cluster; lighting.deferred every
// light at every pixel, kept as the benchmark's and the tests' baseline.
enum class FrameLighting { tiled, deferred };

// Every pass of the frame, in frame order (the graph sorts them by their dependencies): the
// stages below, and the names of what flows between them. A frame assembled otherwise (a pass
// put between two stages) calls the stages itself.
std::vector<PassDecl> frame_passes(FrameLighting lighting = FrameLighting::tiled);
// frame_passes() with `resolve` in the "taa" stage in place of taa: it writes taa.resolved, which
// post reads (the supersampled reference, passes/assembly/supersample.h).
std::vector<PassDecl> frame_passes_resolved_by(PassDecl resolve, FrameLighting lighting = FrameLighting::tiled);
// Each function adds a stage (PassDecl::stage) or two.
// Frame constants and culling ("setup"), shadow maps ("shadows"), the reflection probes' captures
// ("probes"), depth, G-buffer, decals and what is derived from them ("geometry").
void add_scene_passes(std::vector<PassDecl>& passes);
// "lighting": light lists, the sun's shadow mask, the sky, diffuse and specular light, and
// lighting.composite's lit colour, lighting.lit.
void add_lighting_passes(std::vector<PassDecl>& passes, FrameLighting lighting);
// frame_passes() puts "taa" between them: taa resolves lighting.lit into taa.resolved, the `lit`
// post reads.
// "post": bloom, exposure and tonemap, reading the HDR colour `lit`; tonemap writes final.ldr.
void add_post_passes(std::vector<PassDecl>& passes, const std::string& lit);
// Every pass a frame of either lighting runs: where replay finds a recorded pass's declaration.
std::vector<PassDecl> all_passes();

// What the frame must produce: the displayed image, and the depth-summary and light-list
// resources whose consumers (SSR, fog, AO's temporal pass) have not landed yet, so they are
// rendered and recorded.
std::vector<std::string> frame_sinks();

}  // namespace nightcap
