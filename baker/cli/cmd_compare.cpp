// `clothbake compare A.exr B.exr`: error metrics of B against reference A,
// optionally a heat map, a JSON report and a pass/fail bound (for tests).

#include <cstdio>
#include <filesystem>
#include <memory>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/option_range.h"
#include "cli/commands.h"
#include "core/util/error.h"
#include "io/image_compare.h"
#include "io/image_io.h"

namespace clothbake::cli {

namespace {
struct CompareArgs {
  std::string reference, test, heatmap, sheet;
  bool json = false;
  double threshold = 0.0;
  double max_relative_rmse = -1.0;
  double min_psnr = -1.0;
  int downsample = 1;
};

void run_compare(const CompareArgs& a) {
  Image ref = io::read_image(a.reference);
  Image tst = io::read_image(a.test);
  // Box-average full-size images by the factor; an image already that much
  // smaller than the other (a stored small reference) is left as it is.
  const int f = a.downsample;
  if (f > 1) {
    if (ref.width * f != tst.width) ref = io::downsample(ref, f);
    if (tst.width != ref.width) tst = io::downsample(tst, f);
  }
  io::ImageDiff d;
  try {
    d = io::compare_images(ref, tst, a.threshold);
  } catch (const InputError& e) {
    throw e.in_file(a.test);
  }
  if (!a.heatmap.empty()) io::write_png(a.heatmap, io::error_heatmap(ref, tst), false);
  if (!a.sheet.empty())
    io::write_png(
        a.sheet,
        io::comparison_sheet(ref, tst, std::filesystem::path(a.reference).filename().string(),
                             std::filesystem::path(a.test).filename().string(), d),
        false);
  const nlohmann::json j = {{"reference", a.reference},
                            {"test", a.test},
                            {"rmse", d.rmse},
                            {"relative_rmse", d.relative_rmse},
                            {"psnr", d.psnr_db},
                            {"max_error", d.max_error},
                            {"share_over_threshold", d.share_over},
                            {"threshold", d.threshold},
                            {"reference_peak", d.reference_peak},
                            {"reference_mean", d.reference_mean}};
  if (a.json)
    std::printf("%s\n", j.dump(2).c_str());
  else
    std::printf("rmse %.6g  relative rmse %.4f%%  psnr %.2f dB  max %.4g  over %.4g: %.3f%%\n",
                d.rmse, 100.0 * d.relative_rmse, d.psnr_db, d.max_error, d.threshold,
                100.0 * d.share_over);
  if (a.max_relative_rmse >= 0.0 && d.relative_rmse > a.max_relative_rmse)
    throw InputError("--max-relative-rmse", "relative RMSE " + std::to_string(d.relative_rmse) +
                                                " exceeds the bound " +
                                                std::to_string(a.max_relative_rmse));
  if (a.min_psnr >= 0.0 && d.psnr_db < a.min_psnr)
    throw InputError("--min-psnr", "PSNR " + std::to_string(d.psnr_db) + " dB is below the bound " +
                                       std::to_string(a.min_psnr) + " dB");
}
}  // namespace

void register_compare_command(CLI::App& app, Action action) {
  auto args = std::make_shared<CompareArgs>();
  CLI::App* cmd = app.add_subcommand("compare", "Compare an image against a reference (RGB)");
  cmd->add_option("reference", args->reference, "reference image")->required();
  cmd->add_option("test", args->test, "image to measure")->required();
  cmd->add_option("--heatmap", args->heatmap, "write |test - reference| as a heat map PNG");
  cmd->add_option("--sheet", args->sheet,
                  "write reference | test | heat map side by side as a PNG");
  cmd->add_flag("--json", args->json, "print the metrics as JSON");
  cmd->add_option("--threshold", args->threshold,
                  "absolute error counted as 'over' (default 1% of the reference peak)");
  cmd->add_option("--max-relative-rmse", args->max_relative_rmse,
                  "exit 1 when the relative RMSE is above this");
  cmd->add_option("--min-psnr", args->min_psnr, "exit 1 when the PSNR (dB) is below this");
  cmd->add_option("--downsample", args->downsample,
                  "box-average by N x N pixels before comparing (an image already N times "
                  "smaller is taken as is)")
      ->check(in_range(1, 64));
  cmd->callback([args, action] {
    if (action == Action::Run) run_compare(*args);
  });
}

}  // namespace clothbake::cli
