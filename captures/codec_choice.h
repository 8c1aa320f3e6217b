// Which OpenEXR codec an image blob gets, by the kind of data it holds and its format.
#pragma once

#include "captures/blob_codec.h"
#include "passes/core/format.h"
#include "passes/core/resource_kind.h"

namespace nightcap {

ImageEncoding image_encoding_for(ResourceKind kind, const FormatInfo& format);

}  // namespace nightcap
