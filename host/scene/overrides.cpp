// Command-line -D overrides: "dotted.path=value" applied to the DOM before validation, so an
// overridden value is checked exactly like one from the file.
#include <cctype>

#include "host/scene/loader_parts.h"

namespace aw {
namespace scene_detail {
namespace {

struct Segment {
  bool is_index = false;
  std::string key;
  size_t index = 0;
};

std::string trim(const std::string& s) {
  size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

// "objects[0].radius" -> objects, [0], radius. Returns false on malformed syntax.
bool split_path(const std::string& path, std::vector<Segment>* out) {
  size_t i = 0;
  bool expect_name = true;
  while (i < path.size()) {
    if (expect_name) {
      const size_t end = path.find_first_of(".[", i);
      const std::string name =
          path.substr(i, end == std::string::npos ? std::string::npos : end - i);
      if (name.empty()) return false;
      out->push_back(Segment{false, name, 0});
      i = end == std::string::npos ? path.size() : end;
      expect_name = false;
    } else if (path[i] == '.') {
      ++i;
      expect_name = true;
      if (i == path.size()) return false;  // trailing dot
    } else if (path[i] == '[') {
      const size_t close = path.find(']', i);
      if (close == std::string::npos || close == i + 1) return false;
      size_t index = 0;
      for (size_t k = i + 1; k < close; ++k) {
        if (!std::isdigit(static_cast<unsigned char>(path[k]))) return false;
        if (index > 100000000) return false;  // absurd; also guards overflow
        index = index * 10 + static_cast<size_t>(path[k] - '0');
      }
      out->push_back(Segment{true, "", index});
      i = close + 1;
    } else {
      return false;
    }
  }
  return !out->empty();
}

}  // namespace

void apply_overrides(LoadContext& ctx, Json& root, const std::vector<std::string>& overrides) {
  for (const std::string& entry : overrides) {
    const std::string where = "command line -D " + entry;
    const size_t eq = entry.find('=');
    if (eq == std::string::npos) {
      throw SceneError(where + ": expected KEY=VALUE (e.g. render.spp=16)");
    }
    const std::string key = trim(entry.substr(0, eq));
    const std::string raw_value = entry.substr(eq + 1);
    std::vector<Segment> segments;
    if (!split_path(key, &segments)) {
      throw SceneError(where + ": malformed key \"" + key +
                       "\" (expected a dotted path such as materials.floor.diffuse.color or "
                       "objects[0].radius)");
    }

    // The value is JSON when it parses as JSON ("16", "[1,0,0]", "true", "\"x\""), otherwise
    // the literal text, so -D environment.type=constant needs no shell-escaped quotes.
    Json value = Json::parse(raw_value, nullptr, /*allow_exceptions=*/false);
    if (value.is_discarded()) value = Json(raw_value);

    Json* cur = &root;
    std::string path;
    for (const Segment& s : segments) {
      if (!s.is_index) {
        if (cur->is_null()) *cur = Json::object();  // create intermediate objects
        if (!cur->is_object()) {
          throw SceneError(where + ": " + (path.empty() ? "the scene" : path) +
                           " is not an object, cannot set \"" + s.key + "\" in it");
        }
        cur = &(*cur)[s.key];
        path = join_key(path, s.key);
      } else {
        if (cur->is_null()) *cur = Json::array();
        if (!cur->is_array()) {
          throw SceneError(where + ": " + path + " is not an array, cannot index it");
        }
        // Index == size appends (e.g. adding a light from the command line); beyond that
        // there would be holes.
        if (s.index > cur->size()) {
          throw SceneError(where + ": " + join_index(path, s.index) + ": index out of range (" +
                           path + " has " + std::to_string(cur->size()) + " elements)");
        }
        if (s.index == cur->size()) cur->push_back(Json());
        cur = &(*cur)[s.index];
        path = join_index(path, s.index);
      }
    }
    *cur = std::move(value);
    ctx.mark_override(path, entry);
  }
}

}  // namespace scene_detail
}  // namespace aw
