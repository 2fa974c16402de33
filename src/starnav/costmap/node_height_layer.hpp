#pragma once
// The sensing layer of Li et al. 2019 (docs/papers/li2019.md; docs/navigation.md has the rules
// in full): LiDAR returns into a world-aligned grid of 3D nodes, each cell keeping the min and max
// height of its current hits and an integer evidence count. Per scan:
//   hits    every return falling in a cell updates its min/max (the first return of an
//           unobserved cell sets both); a cell hit in the scan gains `hit_gain` evidence (once
//           per scan, however many returns fall in it).
//   passes  every beam is walked over the grid from the sensor to its return (Amanatides-Woo).
//           A cell it crosses before its end cell contradicts the cell's stored hits when the
//           beam's highest point inside the cell lies more than `clear_margin_m` below the
//           cell's max height (there was something there, now the beam passes through): the
//           cell loses `miss_loss` evidence (once per scan), and its stored heights are replaced
//           by the scan's own hits in it, if any. A beam passing above the cell's hits (over low
//           ground) contradicts nothing. In 2D mode every crossed cell is contradicted.
//   result  evidence is clamped to [0, evidence_max]; a cell at 0 is unobserved again.
// Contradictions are judged against the map as it was before the scan, so the order of the
// returns within a scan does not matter.
//
// Its obstacles: the Li 2019 node criteria of terrain/TerrainAnalysis (height spread > max_step,
// mid-height difference to an observed 8-neighbour > tan(max_slope) * distance) on observed cells
// (Nodes3D), or every cell with evidence (Lidar2D). Incremental: only the cells whose heights or
// observed flag changed are re-analysed, in tiles, and those tiles are what it reports changed.
#include <cstdint>
#include <span>
#include <vector>

#include "starnav/costmap/costmap_layer.hpp"
#include "starnav/map/elevation_map.hpp"
#include "starnav/terrain/terrain_analysis.hpp"

namespace starnav {

class NodeHeightLayer final : public CostmapLayer {
 public:
  NodeHeightLayer(const GridGeometry& geometry, const NodeMapParams& params);
  std::string_view name() const override { return "node_height"; }
  void on_scan(const CostmapScan& scan, std::vector<CellRect>& changed, CostmapScanStats& stats) override;
  void contribute(const CellRect& rect, std::span<std::uint8_t> obstacles, std::span<std::uint8_t> observed) const override;
  const ElevationMap* heights() const override { return params_.mode == NodeMapMode::Nodes3D ? &elevation_ : nullptr; }
  void recompute() override;

  int evidence(int x, int y) const { return evidence_[geometry_.index(x, y)]; }
  const ElevationMap& elevation() const { return elevation_; }
  // Valid in Nodes3D mode only.
  const TerrainAnalysis& analysis() const { return analysis_; }

 private:
  struct Touched {
    std::uint32_t index;
    double old_lo, old_hi;
    bool old_observed;
  };
  void walk_beam(const Vec2& a, const Vec2& b, double za, double zb, std::uint32_t end_cell);
  void touch(std::uint32_t i);
  bool obstacle(std::size_t i) const {
    return params_.mode == NodeMapMode::Nodes3D ? analysis_.li_blocked_mask()[i] != 0 : evidence_[i] > 0;
  }

  GridGeometry geometry_;
  NodeMapParams params_;
  std::vector<std::uint8_t> evidence_;
  std::vector<double> lo_, hi_;
  ElevationMap elevation_;
  TerrainAnalysis analysis_;
  // Per-scan scratch: stamps say whether a cell was hit / contradicted in the current scan.
  std::uint32_t scan_ = 0;
  std::vector<std::uint32_t> hit_stamp_, miss_stamp_, touch_stamp_;
  std::vector<Touched> touched_;
  std::vector<std::uint8_t> tile_dirty_;
  std::vector<std::uint32_t> dirty_tiles_;
  bool any_evidence_ = false;
};

}  // namespace starnav
