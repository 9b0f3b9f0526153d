#pragma once
// Study kind "strip_height" (issue 19, docs/studies.md): fig1 on the antiplane strip (docs/model.md §9) at
// several heights H, both models, against the 1D chain (bulk.height = 0) as the H -> 0 line. Pure analysis
// of study results (no I/O).
#include <vector>

#include "studies/study.hpp"

namespace slipfront::studies {

/// The largest relative difference to the 1D events the smallest height may show before the analysis
/// flags it (docs/model.md §9.2: the strip tends to the chain at second order in H; the issue asks for
/// H = 0.25 within 0.5 %).
inline constexpr double strip_height_thin_tolerance = 0.005;

/// Tables `strip_height` (one row per height and row spacing dy, the chain first as H = 0: H/l_e, eps = (H/l_e)^2,
/// t*, t^, c_slow, c_transient, x_arrest of both models, each also relative to the chain's) and, when one height ran at
/// several dy, `strip_height_dy` (each coarser dy against the finest); scalars: the chain's events, the
/// smallest height's largest relative difference to them, the observed order in H over the thin heights;
/// notes: the H -> 0 check (flagged when above strip_height_thin_tolerance), events that were not measured.
void analyse_strip_height(StudyReport& rep, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                          const std::vector<std::vector<ModelResult>>& res);

}  // namespace slipfront::studies
