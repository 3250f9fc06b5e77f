#pragma once
// The hashed-shading thesis's own per-frame light-calculation counts, as
// published in its data repository:
//   <root>/frames/{ns, ts/<tile>, cs/<tile>}/<pipeline>/<scene>/
//       lc_data.json  {"frames": [{"frame": N, "n_calc": C}, ...]}
//       config.json   the run's settings (viewport, tile_size, camera, lights)
// ns = naive, ts = tiled, cs = clustered; <tile> = tile size in pixels.
//
// What the counts are (from the thesis's counting shaders and the data
// itself): tiled and clustered sum, over the pixels, the length of the
// pixel's tile or cluster light list. The naive "ns" series is NUM_LIGHTS x
// covered pixels divided by 10: the companion "resolution/ns-old" series holds
// exactly 10x the "ns" values (where it did not overflow 32 bits) and never
// exceeds NUM_LIGHTS x pixels, while "ns" never exceeds a tenth of it. Callers
// compare naive counts after multiplying by `naive_scale` (10).
#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace ml {

struct ReferenceSeries {
  std::string kind;       // "ns" | "ts" | "cs"
  unsigned tile = 0;      // tile size in pixels; 0 for ns
  std::string id;         // "ns", "ts/16", "cs/8"
  std::string lc_path;    // lc_data.json
  std::string config_path;
  unsigned width = 320, height = 320;  // from config.json (viewport)
  std::string light_file;              // file name of the run's light set, e.g. "70#1x_1y_1z.json"
  float fovy = 45.0f, near_plane = 0.01f, far_plane = 4000.0f;
  std::map<std::size_t, double> counts;  // frame -> n_calc as published
};

struct ThesisReference {
  std::string frames_dir;  // the resolved <root>/frames
  std::string scene;       // scene folder name
  std::string pipeline;    // "deferred"
  std::vector<ReferenceSeries> series;  // ns first, then ts, then cs, by tile
  std::vector<std::string> notes;       // e.g. folders with a config but no lc_data.json
};

// `dir` may be the thesis-suite root, its reference/, reference/light_calculations/
// or the frames/ folder itself. `scene` empty: the only scene present. Throws
// UserError naming the folder or file when nothing usable is found or a file is malformed.
ThesisReference loadThesisReference(const std::string& dir, const std::string& scene,
                                    const std::string& pipeline = "deferred");

// Reads {"frames": [{"frame", "n_calc"}]}; UserError naming the file otherwise.
std::map<std::size_t, double> readLcData(const std::string& path);

}  // namespace ml
