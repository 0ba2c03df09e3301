// Validation helpers shared by the scene loader's translation units: where a JSON path came
// from (file position or -D override), error and warning formatting, and typed readers that
// reject anything the format does not allow. Private to host/scene.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <initializer_list>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "host/scene/located_json.h"
#include "host/scene/texture_desc.h"

namespace aw {
namespace scene_detail {

// A JSON value together with its dotted path, so every reader can name it in a message.
struct Node {
  const Json* j;
  std::string path;
};

class LoadContext {
 public:
  // `file` is the scene path as given (messages use it verbatim); `text` its contents and
  // `doc` the parsed JSON with positions; both must outlive the context.
  LoadContext(std::string file, const std::string* text, const LocatedJson* doc);

  const std::string& file() const { return file_; }

  // Marks `path` (and everything below it) as coming from the command line override
  // `override_text` ("render.spp=16"); messages about it then say "command line -D ...".
  void mark_override(const std::string& path, const std::string& override_text);

  // "FILE:LINE:COL" of the key at `path` (or of its nearest located ancestor), or
  // "command line -D ..." for overridden values, or "FILE" when nothing is known.
  std::string where(const std::string& path) const;

  // Throws SceneError("WHERE: PATH: message").
  [[noreturn]] void fail(const std::string& path, const std::string& message) const;
  // Prints "WHERE: warning: PATH: message" to stderr once and keeps it for Scene::warnings.
  void warn(const std::string& path, const std::string& message);

  std::vector<std::string> take_warnings() { return std::move(warnings_); }

  // The "textures" section's names and indices, for {"texture": NAME} references (set once
  // the section is read; null before).
  void set_textures(const std::map<std::string, uint32_t>* t) { textures_ = t; }
  const std::map<std::string, uint32_t>* textures() const { return textures_; }

 private:
  const std::map<std::string, uint32_t>* textures_ = nullptr;
  std::string file_;
  const LocatedJson* doc_;
  LineMap lines_;
  std::map<std::string, std::string> overrides_;  // path -> "path=value" as typed
  std::vector<std::string> warnings_;
};

// ---- formatting ----------------------------------------------------------------------------

// Shortest decimal spelling that reads back as the same double ("0.1", "1", "1e+30").
std::string format_number(double v);
// A JSON value as the user wrote it, shortened for messages: "glass" keeps its quotes.
std::string describe(const Json& j);

// ---- typed readers -------------------------------------------------------------------------
// All of them throw SceneError through `ctx.fail` naming the node's path.

Node child(const Node& parent, const std::string& key);  // parent must be an object
Node element(const Node& parent, size_t index);          // parent must be an array

// Requires an object whose keys are all in `allowed`; an unknown key is an error naming it
// (with a "did you mean" suggestion), because a typo must never silently render a default.
void expect_object(const LoadContext& ctx, const Node& n, const std::vector<std::string>& allowed);
void expect_object_any_keys(const LoadContext& ctx, const Node& n);
void expect_array(const LoadContext& ctx, const Node& n);
// Member lookup: nullptr-like node (j == nullptr) when absent.
bool has(const Node& obj, const std::string& key);
// Error "missing required key" reported at the enclosing object.
Node require(const LoadContext& ctx, const Node& obj, const std::string& key);

double read_number(const LoadContext& ctx, const Node& n);
int64_t read_integer(const LoadContext& ctx, const Node& n);
bool read_bool(const LoadContext& ctx, const Node& n);
std::string read_string(const LoadContext& ctx, const Node& n);
glm::dvec3 read_vec3(const LoadContext& ctx, const Node& n);
// A colour: [r, g, b] or a single number for grey. {"texture": NAME} is an error here (only
// material inputs take textures: read_texture_ref).
glm::dvec3 read_colour(const LoadContext& ctx, const Node& n);
// A scalar: a number; {"texture": NAME} is the same error.
double read_scalar_input(const LoadContext& ctx, const Node& n);
// {"texture": NAME, "channel": "r"|"g"|"b"|"a"|"luminance"|"rgb", "multiplier": M, "offset": O}
// (docs/scene-format.md#textures): NAME must be in the textures section; a colour input takes
// "rgb" (the default) or one channel as grey, a scalar input one channel or "luminance" (the
// default).
bool is_texture_reference(const Json& j);
TextureRef read_texture_ref(const LoadContext& ctx, const Node& n, bool colour);

// Range-checked reads for settings where an out-of-range value is an error (not clamped).
// `lo_open`/`hi_open` make the bound exclusive.
struct Range {
  double lo;
  double hi;
  bool lo_open = false;
  bool hi_open = false;
  bool contains(double v) const;
  std::string describe() const;  // "in (0, 180)", ">= 1", "> 0"
};
double read_number_in(const LoadContext& ctx, const Node& n, const Range& r);
int read_int_in(const LoadContext& ctx, const Node& n, int64_t lo, int64_t hi);

// Enumerations: a string from `values`; anything else is an error listing the choices.
template <class E>
E read_enum(const LoadContext& ctx, const Node& n,
            const std::vector<std::pair<std::string, E>>& values) {
  const std::string s = read_string(ctx, n);
  for (const auto& v : values) {
    if (v.first == s) return v.second;
  }
  std::string list;
  for (const auto& v : values) list += (list.empty() ? "" : ", ") + v.first;
  ctx.fail(n.path, "unknown value \"" + s + "\"; expected one of: " + list);
}

// Levenshtein-based suggestion among `candidates` ("" when nothing is close).
std::string closest(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace scene_detail
}  // namespace aw
