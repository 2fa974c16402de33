#pragma once
// Small helpers shared by the CLI commands: argument parsing that names the flag in errors,
// output-file rules (conventions.md: never overwrite without --force).
#include <string>

#include "starnav/core/geometry.hpp"
#include "starnav/io/map_file.hpp"

namespace starnav::cli {

// Parses "X,Y" (two finite numbers); throws Error naming `flag` otherwise.
Vec2 parse_xy(const std::string& text, const std::string& flag);

// Throws Error when `path` exists and `force` is false, or its folder does not exist.
void check_output_path(const std::string& path, bool force, const std::string& flag);

// The format to write for an output file name; .yaml means an elevation sidecar for elevation
// maps and a map_server map for occupancy grids.
MapFormat output_map_format(const std::string& path, bool elevation);

// True for a .png picture, false for .svg; throws Error naming `flag` for anything else.
bool picture_is_png(const std::string& path, const std::string& flag);

}  // namespace starnav::cli
