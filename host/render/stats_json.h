// A render's statistics as JSON: what `archwave --stats-json FILE` writes and what the
// benchmark suite (scripts/bench_suite.py) reads, so no one parses the human summary.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "host/render/render.h"
#include "host/scene/scene.h"

namespace aw {

// Every RenderStats field plus the image size, the requested and completed spp, the seed and
// render_seconds (total minus BVH, kernel build and setup: the time the samples took).
nlohmann::json stats_to_json(const RenderResult& result, const Scene& scene);

// Writes stats_to_json to `path` (pretty-printed); throws OutputError when it cannot.
void write_stats_json(const std::string& path, const RenderResult& result, const Scene& scene);

}  // namespace aw
