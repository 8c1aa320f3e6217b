// shadow.local_moments' storage of 4-moment shadow maps (Peters and Klein 2015, "Moment Shadow
// Mapping", section 4.3): the moments b = (t, t², t³, t⁴) of linear depth t ∈ [0, 1] go through
// the paper's affine map q = A·b + (0.035955884801, 0, 0, 0), which spreads the curve of
// (t, t², t³, t⁴), and with it every filtered mixture of its points, over [0, 1]⁴ so that 16-bit
// UNORM keeps enough of their differences for the reconstruction. Written by
// shadow.local_moments, undone by lighting.tiled; being linear, it commutes with the blur and the
// bilinear lookup. A's inverse is computed in exact arithmetic from the paper's A and rounded
// here; LocalShadows.MomentReconstructionMatchesClosedForm encodes with its own copy of A, so a
// wrong inverse fails it.

// Columns of A (GLSL matrices are column-major): A's rows are (−2.07…, 32.23…, −68.57…, 39.37…), …
const mat4 kMomentEncode = mat4(-2.07224649, 13.7948857237, 0.105877704, 9.7924062118,  //
                                32.23703778, -59.4683975703, -1.9077466311, -33.7652110555,  //
                                -68.571074599, 82.0359750338, 9.3496555107, 47.9456096605,  //
                                39.3703274134, -35.364903257, -6.6543490743, -23.9728048165);
const vec4 kMomentOffset = vec4(0.035955884801, 0.0, 0.0, 0.0);
const mat4 kMomentDecode = mat4(0.2227744146, 0.1549679261, 0.1451988946, 0.1631274430,  //
                                0.0771972861, 0.1394629427, 0.2120202157, 0.2591432266,  //
                                0.7926986637, 0.7963415838, 0.7258694464, 0.6539092497,  //
                                0.0319417555, -0.1722823173, -0.2758014811, -0.3376131734);

vec4 encode_moments(vec4 b) { return kMomentEncode * b + kMomentOffset; }
vec4 decode_moments(vec4 q) { return kMomentDecode * (q - kMomentOffset); }
