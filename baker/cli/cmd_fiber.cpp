// `clothbake fiber`: evaluate the fibre reflection model (PAPER.md s.3) for one
// tangent, light and view, print the result as one JSON object, and optionally
// plot the response over all view directions of the upper hemisphere.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "io/enum_names.h"
#include "core/util/error.h"
#include "core/fiber/fiber_model.h"
#include "core/fiber/fiber_table.h"
#include "core/util/image.h"
#include "io/image_io.h"

namespace clothbake::cli {

namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr float kMaxAspect = 1.0e4f;  // the core clamps here (fiber_model.h)
constexpr int kMaxSamples = 1 << 20;

struct FiberArgs {
  double aspect = EllipsoidFiberParams{}.aspect;
  std::string tangent, light, view;
  int samples = EllipsoidFiberParams{}.samples;
  double exponent = EllipsoidFiberParams{}.exponent;
  std::string model = "ellipsoid";
  uint64_t seed = 1;
  std::string plot;
};

/// "x,y,z" -> vector; `option` names the flag in the error.
Imath::V3f parse_vector(const std::string& text, const std::string& option) {
  const InputError malformed(option, "expected three comma-separated numbers, got '" + text + "'");
  std::vector<std::string> parts;
  std::stringstream stream(text);
  for (std::string part; std::getline(stream, part, ',');) parts.push_back(part);
  if (parts.size() != 3 || text.empty() || text.back() == ',') throw malformed;
  Imath::V3f v;
  for (int i = 0; i < 3; ++i) {
    const char* begin = parts[i].c_str();
    char* end = nullptr;
    const double value = std::strtod(begin, &end);
    while (end && (*end == ' ' || *end == '\t')) ++end;
    if (end == begin || *end != '\0' || !std::isfinite(value) || std::abs(value) > 1e30)
      throw malformed;
    v[i] = static_cast<float>(value);
  }
  if (v == Imath::V3f(0.0f))
    throw InputError(option, "must not be the zero vector, got '" + text + "'");
  return v;
}

/// A number as a person would write it in an error message.
std::string shown(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", value);
  return buffer;
}

/// The number rounded to 7 significant digits, so the JSON shows float precision.
double significant(float value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.7g", static_cast<double>(value));
  return std::strtod(buffer, nullptr);
}

/// Lambert azimuthal equal-area disk (radius 1) <-> upper hemisphere (z up).
Imath::V3f disk_to_direction(float x, float y) {
  const float r2 = x * x + y * y;
  const float s = std::sqrt(std::max(0.0f, 2.0f - r2));
  return Imath::V3f(x * s, y * s, 1.0f - r2);
}
/// Pixel (x, y) of a `size`-pixel square -> disk coordinates (y up); false outside.
bool pixel_to_disk(int x, int y, int size, float& u, float& v) {
  u = (x + 0.5f) / size * 2.0f - 1.0f;
  v = 1.0f - (y + 0.5f) / size * 2.0f;
  return u * u + v * v <= 1.0f;
}
Imath::V2f direction_to_disk(const Imath::V3f& d) {
  const float sin_half = std::sqrt(std::max(0.0f, (1.0f - d.z) / 2.0f));  // sin(theta / 2)
  const float horizontal = std::sqrt(d.x * d.x + d.y * d.y);
  if (horizontal <= 0.0f) return Imath::V2f(0.0f);
  return Imath::V2f(d.x, d.y) * (std::sqrt(2.0f) * sin_half / horizontal);
}

void fill_disc(Image& image, float cx, float cy, float radius, const float rgb[3]) {
  for (int y = int(cy - radius) - 1; y <= int(cy + radius) + 1; ++y) {
    for (int x = int(cx - radius) - 1; x <= int(cx + radius) + 1; ++x) {
      if (x < 0 || y < 0 || x >= image.width || y >= image.height) continue;
      const float dx = x + 0.5f - cx, dy = y + 0.5f - cy;
      if (dx * dx + dy * dy <= radius * radius) std::copy(rgb, rgb + 3, image.at(x, y));
    }
  }
}

/// A marker: a dot in `rgb` with a dark rim, readable on any colour map value.
void mark(Image& image, float cx, float cy, const float rgb[3]) {
  const float rim[3] = {0.0f, 0.0f, 0.0f};
  fill_disc(image, cx, cy, 5.5f, rim);
  fill_disc(image, cx, cy, 4.0f, rgb);
}

using Response = std::function<FiberResponse(const Imath::V3f& to_eye)>;

// About 85 lines, kept whole: one figure drawn top to bottom (two panels,
// their lobes, the colour bars, the captions), every part placed by the
// layout constants at its top.
/// Two panels (diffuse, specular) of the response over view directions.
Image plot_lobes(const Response& response, const Imath::V3f& tangent, const Imath::V3f& light,
                 const Imath::V3f& view, const std::string& caption) {
  const int disk = 320, pad = 32, top = 58, panel_w = disk + 2 * pad;
  const int bar_y = top + disk + 14, height = bar_y + 100;
  const float background[3] = {0.09f, 0.09f, 0.1f};
  Image canvas(2 * panel_w, height, 3);
  for (int i = 0; i < canvas.width * canvas.height; ++i)
    std::copy(background, background + 3, &canvas.pixels[size_t(i) * 3]);

  // Step 1: evaluate both terms over the disk (parallel over rows, deterministic).
  Image diffuse(disk, disk, 1), specular(disk, disk, 1);
  tbb::parallel_for(0, disk, [&](int y) {
    for (int x = 0; x < disk; ++x) {
      float u, v;
      if (!pixel_to_disk(x, y, disk, u, v)) continue;
      const FiberResponse r = response(disk_to_direction(u, v));
      *diffuse.at(x, y) = r.diffuse;
      *specular.at(x, y) = r.specular;
    }
  });

  // Step 2: colour map each panel over [0, its maximum], with a colour bar.
  const char* titles[2] = {"diffuse", "specular"};
  const Image* terms[2] = {&diffuse, &specular};
  for (int p = 0; p < 2; ++p) {
    float low = std::numeric_limits<float>::infinity(), peak = 0.0f;  // over the disk only
    for (int y = 0; y < disk; ++y) {
      for (int x = 0; x < disk; ++x) {
        float u, v;
        if (!pixel_to_disk(x, y, disk, u, v)) continue;
        low = std::min(low, *terms[p]->at(x, y));
        peak = std::max(peak, *terms[p]->at(x, y));
      }
    }
    const bool constant = peak - low <= 1e-6f * peak;  // e.g. Kajiya-Kay's diffuse
    const float hi = peak > 0.0f ? peak : 1.0f;
    const Image mapped = io::color_map(*terms[p], "inferno", 0.0f, hi);
    const int x0 = p * panel_w + pad;
    for (int y = 0; y < disk; ++y) {
      for (int x = 0; x < disk; ++x) {
        float u, v;
        if (pixel_to_disk(x, y, disk, u, v))
          std::copy(mapped.at(x, y), mapped.at(x, y) + 3, canvas.at(x0 + x, top + y));
      }
    }
    Image ramp(disk, 1, 1);
    for (int x = 0; x < disk; ++x) ramp.pixels[x] = hi * (x + 0.5f) / disk;
    const Image ramp_rgb = io::color_map(ramp, "inferno", 0.0f, hi);
    for (int y = 0; y < 10; ++y)
      std::copy(ramp_rgb.pixels.begin(), ramp_rgb.pixels.end(), canvas.at(x0, bar_y + y));

    // Markers: the tangent as an axis (either end may face up), light and view if above.
    const float cyan[3] = {0.2f, 0.9f, 1.0f}, green[3] = {0.3f, 1.0f, 0.3f},
                white[3] = {1.0f, 1.0f, 1.0f};
    auto place = [&](const Imath::V3f& d, const float rgb[3]) {
      const Imath::V2f q = direction_to_disk(d);
      mark(canvas, x0 + (q.x + 1.0f) * 0.5f * disk, top + (1.0f - q.y) * 0.5f * disk, rgb);
    };
    if (tangent.z >= 0.0f) place(tangent, cyan);
    if (tangent.z <= 0.0f) place(-tangent, cyan);
    if (view.z >= 0.0f) place(view, white);
    if (light.z >= 0.0f) place(light, green);

    char range[64];
    std::snprintf(range, sizeof range, constant ? "%s  (constant %.3g)" : "%s  (0 .. %.3g)",
                  titles[p], peak);
    io::draw_label(canvas, x0, 24, range, 18);
    io::draw_label(canvas, x0 + disk / 2 - 7, top - 6, "+y", 12, 0.7f, 0.7f, 0.7f);
    io::draw_label(canvas, x0 + disk + 4, top + disk / 2 + 4, "+x", 12, 0.7f, 0.7f, 0.7f);
    io::draw_label(canvas, x0, bar_y + 26, "0", 12, 0.8f, 0.8f, 0.8f);
    char peak_text[32];
    std::snprintf(peak_text, sizeof peak_text, "%.3g", peak);
    io::draw_label(canvas, x0 + disk - 30, bar_y + 26, peak_text, 12, 0.8f, 0.8f, 0.8f);
  }

  // Step 3: what the picture shows.
  const float grey = 0.85f;
  io::draw_label(canvas, pad, height - 48, caption, 13, grey, grey, grey);
  io::draw_label(canvas, pad, height - 29,
                 "response over view directions on the upper hemisphere (z up), "
                 "Lambert equal-area disk",
                 13, grey, grey, grey);
  io::draw_label(canvas, pad, height - 10,
                 light.z >= 0.0f ? "cyan: tangent axis,  green: light,  white: view"
                                 : "cyan: tangent axis,  white: view,  light below the horizon",
                 13, grey, grey, grey);
  return canvas;
}

/// The model and directions of the arguments, every value checked.
struct FiberInputs {
  FiberModelKind kind;
  Imath::V3f tangent, light, view;  ///< unit vectors
};

FiberInputs check_fiber_args(const FiberArgs& args) {
  if (!(args.aspect >= 1.0 && args.aspect <= kMaxAspect))
    throw InputError("--aspect", "must be a number in [1, 10000], got " + shown(args.aspect));
  if (args.samples < 1 || args.samples > kMaxSamples)
    throw InputError("--samples", "must be in [1, " + std::to_string(kMaxSamples) + "], got " +
                                      std::to_string(args.samples));
  if (!(args.exponent > 0.0 && std::isfinite(args.exponent)))
    throw InputError("--exponent", "must be a number > 0, got " + shown(args.exponent));
  FiberModelKind kind;
  if (!io::parse_enum(io::k_fiber_model_names, args.model, kind))
    throw InputError("--model", "expected one of " + io::enum_list(io::k_fiber_model_names) +
                                    ", got '" + args.model + "'");
  return {kind, parse_vector(args.tangent, "--tangent").normalized(),
          parse_vector(args.light, "--light").normalized(),
          parse_vector(args.view, "--view").normalized()};
}

void run_fiber(const FiberArgs& args) {
  // Step 1: check every value before any work or output.
  const FiberInputs inputs = check_fiber_args(args);
  const FiberModelKind kind = inputs.kind;
  const Imath::V3f tangent = inputs.tangent, light = inputs.light, view = inputs.view;

  // Step 2: the model.
  EllipsoidFiberParams params;
  params.aspect = static_cast<float>(args.aspect);
  params.exponent = static_cast<float>(args.exponent);
  params.samples = args.samples;
  FiberTableParams table_params;
  table_params.fiber = params;
  table_params.seed = args.seed;
  const FiberTable table =
      kind == FiberModelKind::Table ? FiberTable::build(table_params) : FiberTable();
  const Response response = [&](const Imath::V3f& to_eye) {
    switch (kind) {
      case FiberModelKind::Table:
        return table.eval(tangent, light, to_eye);
      case FiberModelKind::KajiyaKay:
        return kajiya_kay_fiber(tangent, light, to_eye, params.exponent);
      case FiberModelKind::Ellipsoid:
        break;
    }
    return ellipsoid_fiber(tangent, light, to_eye, params, args.seed);
  };
  const FiberResponse result = response(view);
  const FiberAngles angles = fiber_angles(tangent, light, view);

  // Step 3: the plot, then the report (so a failed write prints nothing).
  if (!args.plot.empty()) {
    char caption[160];
    std::snprintf(caption, sizeof caption,
                  "model %s, aspect %g, Phong exponent %g, %d samples, seed %llu",
                  args.model.c_str(), args.aspect, args.exponent, args.samples,
                  static_cast<unsigned long long>(args.seed));
    io::write_png(args.plot, plot_lobes(response, tangent, light, view, caption),
                  /*linear=*/false);
  }
  int side = static_cast<int>(std::sqrt(double(args.samples)));
  while (side * side < args.samples) ++side;
  nlohmann::json out;
  out["model"] = args.model;
  out["aspect"] = args.aspect;
  out["exponent"] = args.exponent;
  out["samples"] = args.samples;
  out["samples_used"] = side * side;  // rounded up to a k x k stratification
  out["seed"] = args.seed;
  out["tangent"] = {significant(tangent.x), significant(tangent.y), significant(tangent.z)};
  out["light"] = {significant(light.x), significant(light.y), significant(light.z)};
  out["view"] = {significant(view.x), significant(view.y), significant(view.z)};
  out["theta_light_deg"] = significant(float(angles.theta_light * kRadToDeg));
  out["theta_view_deg"] = significant(float(angles.theta_eye * kRadToDeg));
  out["phi_d_deg"] = significant(float(angles.phi_d * kRadToDeg));
  out["diffuse"] = significant(result.diffuse);
  out["specular"] = significant(result.specular);
  if (kind == FiberModelKind::Table)
    out["table"] = {{"theta_bins", table_params.theta_bins},
                    {"phi_bins", table_params.phi_bins},
                    {"entries", table.entry_count()}};
  if (!args.plot.empty()) out["plot"] = args.plot;
  std::printf("%s\n", out.dump(2).c_str());
}

}  // namespace

void register_fiber_command(CLI::App& app, Action action) {
  auto args = std::make_shared<FiberArgs>();
  CLI::App* cmd = app.add_subcommand(
      "fiber", "Evaluate the fibre reflection model (PAPER.md s.3) for one configuration");
  cmd->add_option("--aspect", args->aspect, "Long / short semi-axis of the ellipsoid, >= 1")
      ->capture_default_str();
  cmd->add_option("--tangent", args->tangent, "Fibre axis x,y,z")->required();
  cmd->add_option("--light", args->light, "Direction to the light x,y,z")->required();
  cmd->add_option("--view", args->view, "Direction to the eye x,y,z")->required();
  cmd->add_option("--samples", args->samples, "Jittered silhouette samples (rounded up to k*k)")
      ->capture_default_str();
  cmd->add_option("--exponent", args->exponent, "Phong exponent n, > 0")->capture_default_str();
  cmd->add_option("--model", args->model, "ellipsoid | table | kajiya-kay")->capture_default_str();
  cmd->add_option("--seed", args->seed, "Jitter seed")->capture_default_str();
  cmd->add_option("--plot", args->plot, "Write a PNG of the response over view directions");
  cmd->callback([args, action] {
    if (action == Action::Run)
      run_fiber(*args);
    else
      (void)check_fiber_args(*args);
  });
}

}  // namespace clothbake::cli
