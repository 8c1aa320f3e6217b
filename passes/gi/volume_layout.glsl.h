// The GI volume's layout, as gi.plan (CPU) writes it and gi.volume and lighting.composite read it
// (std140; passes/core/gpu_layout.glsl.h says how this header is read by both compilers).
//
// The volume: cells³ cubic cells of cell_metres around the camera, on a world-aligned grid (cell
// g holds world points [g, g + 1) · cell_metres). Each cell holds the irradiance about every
// normal as 9 spherical-harmonic coefficients per colour in sky.irradiance's form (convolved with
// the clamped cosine over π: Σ c_i Y_i(n) times the albedo is the reflected radiance). gi.volume
// is RGBA16F, cells × cells × kGiVolumeTexels · cells: a cell's 27 numbers, coefficient-major
// (c0.r, c0.g, c0.b, c1.r, …), four to a texel, its texel k in slice block k. A cell of world
// index g lies at texel g mod cells (toroidal: the volume scrolls with the camera without moving
// what it holds; the cells that scroll in overwrite those that scroll out).
#ifndef NIGHTCAP_GI_VOLUME_LAYOUT_GLSL_H
#define NIGHTCAP_GI_VOLUME_LAYOUT_GLSL_H

#include "../core/gpu_layout.glsl.h"

// Texels a cell's 27 coefficients take (the last one's alpha unused).
NC_CONST(uint, kGiVolumeTexels, 7u)
// Invocations of gi.volume's workgroups along each axis.
NC_CONST(uint, kGiVolumeGroupSide, 4u)

#define NC_GPU_GI_VOLUME_FIELDS(F, A, P)                                              \
  /* xyz: the volume's lowest corner relative to the camera; w: a cell's side in      \
     metres */                                                                        \
  F(vec4, origin)                                                                     \
  /* xyz: the world index of the volume's lowest cell; w: cells per side */           \
  F(ivec4, origin_cell)                                                               \
  /* x: the bands lighting.composite evaluates (2: 0–2, 1: 0–1); y: the texels of \
     a cell it reads (7, 3); zw unused */                                             \
  F(uvec4, evaluation)
NC_STRUCT(GpuGiVolume, NC_GPU_GI_VOLUME_FIELDS)

#define NC_GI_VOLUME_CONSTANTS_FIELDS(F, A, P)                          \
  /* xyz: the world index of the box's lowest cell; w: the slots        \
     probes.slots lists */                                              \
  F(ivec4, box_min)                                                     \
  /* xyz: the box's cells along each axis; w: 1 when probes.slots and   \
     probes.irradiance are read */                                      \
  F(uvec4, box_size)                                                    \
  /* x: metres over which a reflection probe's weight fades to 0 at the \
     faces of its box; yzw unused */                                    \
  F(vec4, probes)
NC_PUSH_CONSTANTS(GiVolumeConstants, NC_GI_VOLUME_CONSTANTS_FIELDS)

#endif
