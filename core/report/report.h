// SPDX-License-Identifier: MIT
// What a run produced, for people and programs: the summary table printed at the
// end, the JSON report (--report FILE.json), and the one sentence each stage report is
// rendered as (here only: the progress line, the summary and the HTML report use them).
#pragma once

#include <dthex/pipeline/pipeline.h>

#include <string>

namespace dthex {

//! One line for people on what a stage did, from its typed report (stage_reports.h).
std::string describe(const StageReport& report);

//! What the thickness retry did, over three lines (the second and third indented by two
//! spaces); "" when it did not run.
std::string describe(const ThicknessRetryReport& report);

//! What the retry at a finer eps did, over two or more lines (the later ones indented by two
//! spaces); "" when it did not run.
std::string describe(const FinerRetryReport& report);

//! What the safe repairs of the input did: a line "  repaired: ..." for each repair that
//! changed something (counts and the first ids), "" when none did.
std::string describe(const SurfaceRepairReport& report);

//! The paper-style summary: per stage time and counts, then quality of the input
//! triangles, the coarse triangles, the tets and the hexes, and the distance to the input.
std::string summary_table(const PipelineResult& result, const PipelineOptions& options);

//! The JSON report: input, coarse, tet and hex statistics, histograms, timings, options, version.
//! Each entry of "stages" holds "name", "seconds", "report" (the stage report's fields as
//! numbers, booleans, and strings only for enums and error messages) and "summary" (describe()).
//! With thex_baseline (--compare-thex), that run's report is nested under "thex_baseline".
std::string report_json(const PipelineResult& result, const PipelineOptions& options,
                        const PipelineResult* thex_baseline = nullptr);

}  // namespace dthex
