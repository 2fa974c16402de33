#include "starnav/slam/scan_matcher.hpp"

#include <string>

#include "starnav/core/error.hpp"

namespace starnav {

ScanMatch ScanMatcher::match_to_map(const OccupancyGrid& /*map*/, std::span<const Vec2> /*scan*/, const Pose2& /*guess*/) {
  throw Error("scan matcher '" + std::string(name()) + "' matches scans to scans only, not to a map", {}, 0, "scan_matcher");
}

std::unique_ptr<ScanReference> ScanMatcher::prepare(std::span<const Vec2> /*points*/, double /*search_margin_m*/, int /*search_depth*/) const {
  throw Error("scan matcher '" + std::string(name()) + "' matches two scans at a time; it prepares no reference for repeated matches", {},
              0, "scan_matcher");
}

}  // namespace starnav
