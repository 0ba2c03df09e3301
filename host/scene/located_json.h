// JSON parsing that remembers where every key and value came from.
//
// nlohmann::json does not record source positions, but scene errors must name FILE:LINE:COL
// (docs/scene-format.md, "Errors and exit codes"). We therefore drive nlohmann's own parser
// through its SAX interface with an input iterator that counts the bytes the lexer has
// consumed, build the DOM ourselves, and note the byte offset of each key and value in a side
// table keyed by the dotted JSON path ("materials.glass.refraction.ior", arrays as
// "objects[3].file").
// Private to host/scene.
#pragma once

#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace aw {
namespace scene_detail {

// The deepest nesting of objects and arrays a scene file may have (parse_located_json refuses
// more, at the first bracket beyond it).
constexpr size_t kMaxJsonDepth = 256;

// ordered_json keeps object members in file order: Scene::material_names must follow the file,
// and "the first unknown key" in an error should be the first one the user wrote.
using Json = nlohmann::ordered_json;

// 1-based line and column; columns count UTF-8 code points, as editors do.
struct TextPos {
  int line = 1;
  int col = 1;
};

// Converts byte offsets of one text into line:column. Keeps a pointer to the text, which must
// outlive it.
class LineMap {
 public:
  explicit LineMap(const std::string* text);
  TextPos at(size_t offset) const;

 private:
  const std::string* text_;
  std::vector<size_t> line_starts_;
};

// Byte offsets (into the file text) of a member's key and of its value. For array elements and
// the root, which have no key, both are the start of the value.
struct JsonLoc {
  size_t key = 0;
  size_t value = 0;
};

struct LocatedJson {
  Json root;
  std::map<std::string, JsonLoc> locs;  // dotted path -> offsets
};

struct JsonSyntaxError {
  size_t offset = 0;    // byte offset of the offending token
  std::string message;  // without nlohmann's "[json.exception...] at line..., column..." prefix
};

// Parses `text` (strict JSON, no comments). Returns false and fills `err` on a syntax error or a
// duplicate key; never throws for bad input.
bool parse_located_json(const std::string& text, LocatedJson* out, JsonSyntaxError* err);

// Path building shared by the parser, the validator and the -D overrides, so that the three
// agree on the spelling of a path.
std::string join_key(const std::string& parent, const std::string& key);
std::string join_index(const std::string& parent, size_t index);
// "a.b[2].c" -> "a.b[2]" -> "a.b" -> "a" -> "" (the root).
std::string parent_path(const std::string& path);

}  // namespace scene_detail
}  // namespace aw
