// starnav map render FILE --out picture.svg|picture.png
#include <cctype>
#include <filesystem>
#include <iostream>

#include "cli_util.hpp"
#include "commands.hpp"
#include "starnav/core/error.hpp"
#include "starnav/io/map_file.hpp"
#include "starnav/viz/map_picture.hpp"

namespace starnav::cli {

namespace {

struct MapRenderOptions {
  std::string file;
  std::string out;
  std::string title;
  double pixels_per_cell = 0.0;
  int width_px = 0;
  bool force = false;
};

void run_map_render(const MapRenderOptions& o) {
  const bool png = picture_is_png(o.out, "--out");
  check_output_path(o.out, o.force, "--out");
  if (o.pixels_per_cell < 0.0) throw Error("must be positive", {}, 0, "--pixels-per-cell");
  if (o.width_px < 0) throw Error("must be positive", {}, 0, "--width");
  const LoadedMap m = load_map(o.file);
  std::vector<CommandFile> files;
  add_map_files(files, m, "FILE");
  files.push_back({o.out, "--out"});
  check_distinct_files(files);
  viz::PictureOptions options;
  options.title = o.title.empty() ? std::filesystem::path(o.file).filename().string() : o.title;
  options.pixels_per_cell = png ? 0.0 : o.pixels_per_cell;
  const viz::MapPicture picture = m.is_elevation() ? viz::MapPicture(m.elevation(), options)
                                                   : viz::MapPicture(m.occupancy(), options);
  if (png) {
    const viz::RasterSize size = o.width_px > 0 ? viz::RasterSize::width(o.width_px)
                                                : viz::RasterSize::per_cell(o.pixels_per_cell);
    picture.write_png(o.out, size);
  } else {
    picture.write_svg(o.out);
  }
  std::cout << "wrote " << o.out << "\n";
}

}  // namespace

void register_map_render(CLI::App& map, Context& ctx) {
  auto o = std::make_shared<MapRenderOptions>();
  auto* render = map.add_subcommand("render", "draw a map as SVG or PNG (occupancy in grey; elevation with colour ramp and hillshade)");
  render->add_option("FILE", o->file, "map file")->required();
  render->add_option("--out", o->out, "picture to write (.svg or .png)")->required();
  render->add_option("--title", o->title, "title above the map (default: the file name)");
  render->add_option("--pixels-per-cell", o->pixels_per_cell, "scale (default: automatic, about 800 px across)");
  render->add_option("--width", o->width_px, "PNG width in pixels (instead of --pixels-per-cell)");
  render->add_flag("--force", o->force, "overwrite --out if it exists");
  render->callback([o, &ctx] {
    run_map_render(*o);
    ctx.exit_code = 0;
  });
}

}  // namespace starnav::cli
