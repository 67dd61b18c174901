// SPDX-License-Identifier: MIT
// The HTML report (--report FILE.html): one self-contained page a person opens in a
// browser with no network. Inline CSS, inline SVG histograms and a small hand-written
// canvas 3D viewer, so it works offline, from a mail attachment or a CI artifact.
#pragma once

#include <dthex/pipeline/pipeline.h>

#include <string>

namespace dthex {

//! Most faces embedded per 3D layer, so the page stays a few MB and the viewer
//! interactive. A bigger layer is reduced by vertex clustering (core/report/cluster_surface.h)
//! to at most this many triangles: closed, no holes, every poor hex face unchanged.
constexpr size_t kReportMaxFacesPerLayer = 150000;

struct ReportHtmlOptions {
  size_t max_faces_per_layer = kReportMaxFacesPerLayer;
};

//! The page: stage table, quality tables, SVG histograms of hex shape and scaled
//! Jacobian (the THex baseline's beside them when given), and a 3D view of the input
//! surface, the coarse surface and the hex boundary coloured by quality with the worst
//! hexes marked. Its script sets <body data-render="ok"> once the view is drawn, or
//! data-render="error" and data-render-error="message" when it fails.
std::string report_html(const PipelineResult& result, const PipelineOptions& options,
                        const PipelineResult* thex_baseline = nullptr, const ReportHtmlOptions& html_options = {});

}  // namespace dthex
