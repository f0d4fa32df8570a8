// The report of `penumbra bench shadows`: rows of (scene, technique, parameters) with stage times
// and errors against the ray-traced reference, written as JSON, CSV, a static HTML page and one
// Pareto plot (time against error) per scene as SVG.
//
// Units: times in milliseconds of wall-clock time; rmse_v, bias_v (the signed mean error, positive
// = too bright), max_err_v in units of V (the visible fraction of the light, [0, 1]);
// frac_err_gt_005 a fraction in [0, 1]; rmse_image in [0, 1] (engine/metrics.h says how each is
// measured). rmse_v and bias_v again for the ground, object and contact receivers alone
// (metrics.h, receiverClasses): NaN (null in JSON) where a scene has none.
//
// Files written by writeShadowReport into its directory (each one atomically: a temporary file in
// the same directory renamed over the destination, so a reader never sees a partial file):
//   results.json        {"title", "machine", "scenes": [...], "rows": [toJson(row), ...]}
//   results.csv         csvHeader() then toCsv(row) per row, lines ending in "\n"
//   pareto-<scene>.svg  per scene (file names from paretoPlotFileNames)
//   index.html          static page (inline CSS, no script, no external resource) referring to the
//                       above and to the images the rows and scenes name
// The images themselves (ShadowBenchRow::image, ::heatMap, ShadowBenchScene::referenceImage) are
// written by the caller; the report only refers to them by their paths relative to the directory.
//
// Thread-safety: every function is pure apart from writeShadowReport's files; calls on distinct
// directories may run at once.
#pragma once

#include <string>
#include <vector>

#include "engine/error.h"

namespace penumbra::engine {

struct ShadowBenchRow {
  std::string scene, technique, params;  // params: "name=value,..." as the technique was run
  int views = 0;                         // light views rendered; 0 when not applicable
  double msMaps = 0, msFilter = 0, msPrepare = 0, msEvaluate = 0, msTotal = 0;  // medians over runs
  double rmseV = 0, biasV = 0, maxErrV = 0, fracErrGt005 = 0, rmseImage = 0;
  // By receiver class (metrics.h): ground, object, contact.
  double rmseGround = 0, biasGround = 0, rmseObject = 0, biasObject = 0, rmseContact = 0, biasContact = 0;
  // The spread over runs (fastest and slowest run) of maps, evaluate and total, and the medians of
  // the two parts of maps where a technique has them (shadows::StageTimes: vwss's point generation
  // and splatting; 0 otherwise).
  double msMapsMin = 0, msMapsMax = 0, msEvaluateMin = 0, msEvaluateMax = 0, msTotalMin = 0, msTotalMax = 0;
  double msPoints = 0, msSplat = 0;
  std::string image, heatMap;  // file names relative to the report directory, "" if none
};

struct ShadowBenchScene {
  std::string name, description;
  std::string referenceImage;  // relative to the report directory, "" if none
  std::string referenceNote;   // how the reference was made (samples, cache), shown under it
  int width = 0, height = 0;   // pixels of the images
};

// One line of JSON (no newline) with exactly the keys scene, technique, params, ms_maps, ms_filter,
// ms_prepare, ms_evaluate, ms_total, rmse_v, bias_v, max_err_v, frac_err_gt_005, rmse_v_ground,
// bias_v_ground, rmse_v_object, bias_v_object, rmse_v_contact, bias_v_contact, rmse_image,
// ms_maps_min, ms_maps_max, ms_evaluate_min, ms_evaluate_max, ms_total_min, ms_total_max, ms_points,
// ms_splat, in that order.
// Numbers are written in the shortest form that reads back to the same double; a non-finite
// number (which JSON cannot hold) is written as null.
std::string toJson(const ShadowBenchRow& row);

// The same columns, same order, as CSV (no line terminator). Text fields are quoted per RFC 4180
// when they hold a comma, a double quote, CR or LF (quotes doubled); numbers are written in the
// shortest round-trip form, non-finite ones as "nan", "inf" or "-inf".
std::string csvHeader();
std::string toCsv(const ShadowBenchRow& row);

// Per row of `rows` (whatever their scenes: pass one scene's rows), true when the row is
// Pareto-optimal in (ms_total, rmse_v), both smaller-is-better: no other row is at least as good in
// both and strictly better in one. Equal rows are all optimal together. A row with a non-finite
// ms_total or rmse_v is never optimal and dominates no other row.
std::vector<bool> paretoFront(const std::vector<ShadowBenchRow>& rows);

// "pareto-<name>.svg" per scene, in order: characters other than ASCII letters, digits, '-', '_'
// and '.' become '_' (an empty name becomes "scene"), and a name already taken gets "-2", "-3", ...
std::vector<std::string> paretoPlotFileNames(const std::vector<ShadowBenchScene>& scenes);

// Writes the files listed above into dir, creating it (and its parents) if needed. Sections
// follow the order of `scenes`, table rows the order of `rows`. Fails, before writing anything,
// when two scenes share a name or a row names a scene not in `scenes`; the Error then names
// "report <dir>". A write failure stops at that file and the Error names it; files written before
// it are complete and stay.
Status writeShadowReport(const std::string& dir, const std::vector<ShadowBenchScene>& scenes,
                         const std::vector<ShadowBenchRow>& rows, const std::string& title,
                         const std::string& machineNote);

}  // namespace penumbra::engine
