#pragma once
// Study kind "strip_height" (issue 19, docs/studies.md): fig1 on the antiplane strip (docs/model.md §9) at
// several heights H, both models, against the 1D chain (bulk.height = 0) as the H -> 0 line. The body is each run's
// own (bulk.body): runs on the in-plane strip (docs/model.md §10; the study inplane_height, issue 38) get the same
// analysis in tables and scalars named inplane_height instead of strip_height, so one study can hold the chain and
// both strips. Pure analysis of study results (no I/O).
#include <vector>

#include "studies/study.hpp"

namespace slipfront::studies {

/// The largest relative difference to the 1D events the smallest height may show before the analysis
/// flags it (docs/model.md §9.2: the strip tends to the chain at second order in H; the issue asks for
/// H = 0.25 within 0.5 %).
inline constexpr double strip_height_thin_tolerance = 0.005;

/// Per strip body that ran (the antiplane strip's names below; the in-plane strip's with `inplane_height` for
/// `strip_height`, its notes led by "in-plane strip: "):
/// tables `strip_height` (one row per height and row spacing dy, the chain first as H = 0: H/l_e, eps = (H/l_e)^2,
/// t*, t^, c_slow, c_transient, x_arrest of both models, each also relative to the chain's) and, when one height ran at
/// several dy, `strip_height_dy` (each coarser dy against the finest); scalars: the chain's events, the
/// smallest height's largest relative difference to them, the observed order in H over the thin heights;
/// notes: the H -> 0 check (flagged when above strip_height_thin_tolerance), events that were not measured.
void analyse_strip_height(StudyReport& rep, const std::vector<StudyRun>& runs, const std::vector<Scene>& scenes,
                          const std::vector<std::vector<ModelResult>>& res);

}  // namespace slipfront::studies
