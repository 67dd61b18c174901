// SPDX-License-Identifier: MIT
// The HTML report (--report FILE.html): one self-contained page a person opens in a
// browser with no network. Inline CSS, inline SVG histograms and a small hand-written
// canvas 3D viewer, so it works offline, from a mail attachment or a CI artifact.
#pragma once

#include "core/pipeline.h"

#include <string>

namespace dthex {

//! Most faces embedded per 3D layer. Above it a layer shows a uniform sample of its faces
//! (plus every poor hex face) so the page stays a few MB and the viewer interactive.
constexpr size_t kReportMaxFacesPerLayer = 150000;

//! The page: stage table, quality tables, SVG histograms of hex shape and scaled
//! Jacobian (the THex baseline's beside them when given), and a 3D view of the input
//! surface, the coarse surface and the hex boundary coloured by quality with the worst
//! hexes marked. Its script sets <body data-render="ok"> once the view is drawn, or
//! data-render="error" and data-render-error="message" when it fails.
std::string report_html(const PipelineResult& result, const PipelineOptions& options,
                        const PipelineResult* thex_baseline = nullptr);

}  // namespace dthex
