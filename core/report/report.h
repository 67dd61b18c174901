// SPDX-License-Identifier: MIT
// What a run produced, for people and programs: the summary table printed at the
// end and the JSON report (--report FILE.json).
#pragma once

#include <dthex/pipeline/pipeline.h>

#include <string>

namespace dthex {

//! The paper-style summary: per stage time and counts, then quality of the input
//! triangles, the coarse triangles, the tets and the hexes, and the distance to the input.
std::string summary_table(const PipelineResult& result, const PipelineOptions& options);

//! The JSON report: input, coarse, tet and hex statistics, histograms, timings, options, version.
//! With thex_baseline (--compare-thex), that run's report is nested under "thex_baseline".
std::string report_json(const PipelineResult& result, const PipelineOptions& options,
                        const PipelineResult* thex_baseline = nullptr);

}  // namespace dthex
