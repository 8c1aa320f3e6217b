#include "captures/codec_choice.h"

namespace nightcap {

// Chosen from the resources of the city frame at 1280x720 (2026-11-23, one core each, sizes as
// a fraction of raw bytes; ZIP at zlib level 1 unless named):
//   hdr_colour RGBA16F   ZIP 0.29, ZIP4 0.26 at 0.75x the speed, PIZ 0.33, RLE 0.41
//   colour sRGB8         PIZ 0.25, ZIP 0.36, RLE 0.71
//   colour A2B10G10R10   PIZ 0.18 at 1.5x ZIP's speed, ZIP 0.22
//   motion RG16F         PIZ 0.17 at 1.5x ZIP's speed, ZIP 0.15
//   packed_normal RGBA8  PIZ 0.022, ZIP 0.041
//   depth_stencil        ZIP 0.25, PIZ 0.34
//   linear_depth R32F    ZIP 0.53, PIZ 0.47 at 0.8x the speed
//   depth_minmax RG32F   ZIP 0.57, PIZ 0.55 at 0.7x the speed
//   normal A2B10G10R10   ZIP 0.019, PIZ 0.040
//   material RGBA8       ZIP 0.042, PIZ 0.034
//   lookup_table R8      PIZ 0.84, ZIP 0.87
// Lookup tables of wider channels, measured later (2026-11-27, the city block's frame, sizes in
// bytes): shadow depth D32 PIZ 10.5 M, ZIP 4.6 M; 4-moment shadow maps RGBA16 UNORM PIZ 1.9 M,
// ZIP 0.48 M; LTC tables RGBA32F/RG32F ZIP 2% smaller. PIZ's wavelet works on 16-bit words, which
// splits a float or a 16-bit code it cannot predict.
// stencil and mask (R8_UINT) were not measured: they take lookup_table's choice, the other
// 8-bit integer image.
// light_clusters (R32G32_UINT offsets and counts, 3D) was not measured: mostly zero counts and
// offsets rising by small steps, smooth content, so ZIP.
// Noisy, dithered or 8-bit-per-channel content compresses best with PIZ's wavelet; smooth
// content and float depth with ZIP, whose higher levels cost more time than they save bytes.
// The displayed image (sRGB8 colour) is the exception: every diff reads both sides of it and runs
// FLIP on them, the longest piece of a diff's work. ZIP reads it in 10.5 ms, PIZ in 16.7 (one
// core, the city block's 1280x720 frame, 2026-11-27), for 0.4 MB more per capture (25.6 -> 26.0).
ImageEncoding image_encoding_for(ResourceKind kind, const FormatInfo& format) {
  constexpr ImageEncoding piz{ExrCompression::piz, 1};
  constexpr ImageEncoding zip{ExrCompression::zip, 1};
  switch (kind) {
    case ResourceKind::lookup_table:
      return format.texel_bytes / format.channels == 1 ? piz : zip;
    case ResourceKind::colour:
      return format.encoding == ChannelEncoding::srgb8 ? zip : piz;
    case ResourceKind::packed_normal:
    case ResourceKind::motion:
    case ResourceKind::stencil:
    case ResourceKind::mask:
      return piz;
    case ResourceKind::hdr_colour:
    case ResourceKind::normal:
    case ResourceKind::material:
    case ResourceKind::depth_stencil:
    case ResourceKind::linear_depth:
    case ResourceKind::depth_minmax:
    case ResourceKind::texture:
    case ResourceKind::buffer:
    case ResourceKind::draw_list:
    case ResourceKind::light_clusters:
      return zip;
  }
  return zip;
}

}  // namespace nightcap
