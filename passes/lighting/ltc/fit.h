// The fit of passes/lighting/ltc/ggx_table.h: for each roughness and view angle of the table's
// axes (ltc.h), the M⁻¹ whose LTC best matches the project's GGX × n·l (GGX D, height-correlated
// Smith V, no Fresnel; tests/reference/lighting_reference.h), and the two magnitudes that carry
// its scale and Schlick's Fresnel (ltc.h, TableEntry).
//
// The error is the L3 distance of Heitz et al. 2016, ∫ |D_ltc − ggx/norm|³, estimated with both
// distributions' samples combined by the balance heuristic. The samples come from a fixed
// stratified grid, so the error is a deterministic, continuous function of M⁻¹; Nelder–Mead
// minimises it over M⁻¹'s four stored values, each entry starting from the stored entry before
// it (fit_start), so any entry of a committed table can be refitted on its own.
//
// Not used while rendering: nightcap_ltc_fit (fit_tool.cpp) writes the table, and the tests
// refit entries of it.
#pragma once

#include <functional>

#include "passes/lighting/ltc/ltc.h"

namespace nightcap::ltc {

// The view angles the fit accepts: at exactly 90° the lobe has no visible normals.
inline constexpr double kMinFitCosTheta = 1e-3;

struct FitSettings {
  int size = 64;                // entries per axis
  int error_samples = 32;       // per axis of the stratified grid, from each distribution
  int magnitude_samples = 256;  // per axis, for norm and fresnel
  int max_evaluations = 4000;   // of the error, per entry
};

// The entry at (roughness, cos θv), its fit started from `start`.
TableEntry fit_entry(double roughness, double cos_theta_v, const InverseMatrix& start, const FitSettings& settings);

// Where the fit of entry (row, column) starts: the stored M⁻¹ of the row before it in the same
// column (one step less grazing); on row 0 (normal incidence), of the next rougher column; for
// the roughest entry at normal incidence, the clamped cosine itself.
InverseMatrix fit_start(const Table& table, int row, int column);

// The whole table, in the order fit_start needs. `progress` is told how many entries are done.
Table fit_table(const FitSettings& settings, const std::function<void(int done, int total)>& progress = {});

}  // namespace nightcap::ltc
