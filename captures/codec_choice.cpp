#include "captures/codec_choice.h"

namespace nightcap {

// A kind's compression is its registered KindCompression: deflate is OpenEXR's ZIP, wavelet its
// PIZ. Every kind has taken ZIP at zlib level 1 since ZIP blobs are written by nightcap with libdeflate
// (blob_codec.cpp). Encoding the city frame's images at 1280x720 on one core (2026-11-27, MB
// after encoding), PIZ where it was chosen before against ZIP now:
//   colour A2B10G10R10   PIZ 0.67 in 18.8 ms, ZIP 0.74 in 13.4
//   motion RG16F         PIZ 0.64 in 21.4 ms, ZIP 0.47 in 14.1
//   packed_normal RGBA8  PIZ 0.08 in 23.4 ms, ZIP 0.09 in 22.9
//   mask R8G8, R8_UINT   PIZ 0.07 in 24.4 ms, ZIP 0.04 in 14.1
//   stencil R8_UINT      PIZ 0.01 in 4.3 ms,  ZIP 0.00 in 0.9
//   lookup_table R8      PIZ 0.88 in 17.8 ms, ZIP 0.87 in 12.7
// All images: 22.63 MB in 577 ms with the old choice, 22.49 MB in 549 ms with ZIP alone; PIZ on
// every kind 31.0 MB in 1463 ms. ZIP is also the faster to read (captures/exr_zip.h), and its
// higher levels cost more time than they save bytes (ZIP4 on hdr_colour with zlib, 2026-11-23:
// 0.26 of raw against 0.29, at 0.75x the speed).
ImageEncoding image_encoding_for(ResourceKind kind, const FormatInfo&) {
  const KindCompression& compression = kind_info(kind).compression;
  return {compression.method == KindCompression::Method::wavelet ? ExrCompression::piz : ExrCompression::zip,
          compression.level};
}

}  // namespace nightcap
