#include "host/scene/loader_context.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <limits>

#include "host/scene/scene.h"

namespace aw {
namespace scene_detail {

LoadContext::LoadContext(std::string file, const std::string* text, const LocatedJson* doc)
    : file_(std::move(file)), doc_(doc), lines_(text) {}

void LoadContext::mark_override(const std::string& path, const std::string& override_text) {
  // A later -D that replaces a whole subtree also replaces what earlier -D entries put inside
  // it; forget those so messages name the entry that actually supplied the value.
  for (auto it = overrides_.begin(); it != overrides_.end();) {
    const std::string& p = it->first;
    const bool inside = p.size() > path.size() && p.compare(0, path.size(), path) == 0 &&
                        (path.empty() || p[path.size()] == '.' || p[path.size()] == '[');
    it = inside ? overrides_.erase(it) : std::next(it);
  }
  overrides_[path] = override_text;
}

std::string LoadContext::where(const std::string& path) const {
  // An override on the path or on any ancestor replaced what the file said there, so the
  // file position would be a lie: name the -D entry instead. The nearest one wins.
  for (std::string p = path;; p = parent_path(p)) {
    const auto it = overrides_.find(p);
    if (it != overrides_.end()) return "command line -D " + it->second;
    if (p.empty()) break;
  }
  for (std::string p = path;; p = parent_path(p)) {
    const auto it = doc_->locs.find(p);
    if (it != doc_->locs.end()) {
      const TextPos pos = lines_.at(it->second.key);
      return file_ + ":" + std::to_string(pos.line) + ":" + std::to_string(pos.col);
    }
    if (p.empty()) break;
  }
  return file_;
}

void LoadContext::fail(const std::string& path, const std::string& message) const {
  throw SceneError(where(path) + ": " + (path.empty() ? "" : path + ": ") + message);
}

void LoadContext::warn(const std::string& path, const std::string& message) {
  std::string line = where(path) + ": warning: " + (path.empty() ? "" : path + ": ") + message;
  std::fprintf(stderr, "%s\n", line.c_str());
  warnings_.push_back(std::move(line));
}

std::string format_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  // Integers print as integers ("180", not "1.8e+02"), which is how users write them.
  if (v == std::floor(v) && std::fabs(v) < 1e15) {
    std::snprintf(buf, sizeof buf, "%.0f", v);
    return buf;
  }
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string describe(const Json& j) {
  // Replace invalid UTF-8 (possible in -D values, which nlohmann never validated) instead of
  // letting dump() throw.
  std::string s = j.dump(-1, ' ', false, Json::error_handler_t::replace);
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

Node child(const Node& parent, const std::string& key) {
  const auto it = parent.j->find(key);
  return Node{it == parent.j->end() ? nullptr : &*it, join_key(parent.path, key)};
}

Node element(const Node& parent, size_t index) {
  return Node{&(*parent.j)[index], join_index(parent.path, index)};
}

bool has(const Node& obj, const std::string& key) { return obj.j->contains(key); }

std::string closest(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = std::numeric_limits<size_t>::max();
  for (const std::string& c : candidates) {
    // Plain Levenshtein distance; the candidate lists are a few dozen short words.
    std::vector<size_t> row(c.size() + 1);
    for (size_t j = 0; j <= c.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= word.size(); ++i) {
      size_t diag = row[0];
      row[0] = i;
      for (size_t j = 1; j <= c.size(); ++j) {
        const size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (word[i - 1] == c[j - 1] ? 0 : 1)});
        diag = up;
      }
    }
    if (row[c.size()] < best_distance) {
      best_distance = row[c.size()];
      best = c;
    }
  }
  // Only suggest what is plausibly a typo of the word, not any short key.
  if (best_distance <= 2 && best_distance < word.size()) return best;
  return "";
}

void expect_object_any_keys(const LoadContext& ctx, const Node& n) {
  if (!n.j->is_object()) ctx.fail(n.path, "expected an object, got " + describe(*n.j));
}

void expect_object(const LoadContext& ctx, const Node& n, const std::vector<std::string>& allowed) {
  expect_object_any_keys(ctx, n);
  for (const auto& item : n.j->items()) {
    bool known = false;
    for (const std::string& a : allowed) known = known || a == item.key();
    if (known) continue;
    std::string message = "unknown key \"" + item.key() + "\"";
    const std::string suggestion = closest(item.key(), allowed);
    if (!suggestion.empty()) {
      message += " (did you mean \"" + suggestion + "\"?)";
    } else {
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      message += "; allowed keys here: " + list;
    }
    ctx.fail(join_key(n.path, item.key()), message);
  }
}

void expect_array(const LoadContext& ctx, const Node& n) {
  if (!n.j->is_array()) ctx.fail(n.path, "expected an array, got " + describe(*n.j));
}

Node require(const LoadContext& ctx, const Node& obj, const std::string& key) {
  Node c = child(obj, key);
  // The key is not there, so its own position does not exist: point at the enclosing object.
  if (c.j == nullptr) ctx.fail(obj.path, "missing required key \"" + key + "\"");
  return c;
}

double read_number(const LoadContext& ctx, const Node& n) {
  if (!n.j->is_number()) ctx.fail(n.path, "expected a number, got " + describe(*n.j));
  const double v = n.j->get<double>();
  if (!std::isfinite(v)) ctx.fail(n.path, "expected a finite number, got " + describe(*n.j));
  return v;
}

int64_t read_integer(const LoadContext& ctx, const Node& n) {
  const Json& j = *n.j;
  if (j.is_number_unsigned()) {
    const uint64_t u = j.get<uint64_t>();
    if (u > static_cast<uint64_t>(std::numeric_limits<int64_t>::max())) {
      ctx.fail(n.path, "integer " + describe(j) + " is too large");
    }
    return static_cast<int64_t>(u);
  }
  if (j.is_number_integer()) return j.get<int64_t>();
  if (j.is_number_float()) {
    // 16.0 is accepted as 16 (some tools write every number as a float); 16.5 is not.
    const double v = j.get<double>();
    if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 9.0e18) {
      return static_cast<int64_t>(v);
    }
  }
  ctx.fail(n.path, "expected an integer, got " + describe(j));
}

bool read_bool(const LoadContext& ctx, const Node& n) {
  if (!n.j->is_boolean()) ctx.fail(n.path, "expected true or false, got " + describe(*n.j));
  return n.j->get<bool>();
}

std::string read_string(const LoadContext& ctx, const Node& n) {
  if (!n.j->is_string()) ctx.fail(n.path, "expected a string, got " + describe(*n.j));
  return n.j->get<std::string>();
}

glm::dvec3 read_vec3(const LoadContext& ctx, const Node& n) {
  if (!n.j->is_array() || n.j->size() != 3) {
    ctx.fail(n.path, "expected an array of 3 numbers, got " + describe(*n.j));
  }
  glm::dvec3 v;
  for (int i = 0; i < 3; ++i) v[i] = read_number(ctx, element(n, static_cast<size_t>(i)));
  return v;
}

bool is_texture_reference(const Json& j) { return j.is_object() && j.contains("texture"); }

namespace {
[[noreturn]] void fail_texture(const LoadContext& ctx, const Node& n) {
  ctx.fail(n.path, "only material inputs take a texture (this value refers to texture " +
                       describe((*n.j)["texture"]) + ")");
}
}  // namespace

TextureRef read_texture_ref(const LoadContext& ctx, const Node& n, bool colour) {
  expect_object(ctx, n, {"texture", "channel", "multiplier", "offset", "uv_set"});
  const Node name_node = child(n, "texture");
  const std::string name = read_string(ctx, name_node);
  TextureRef r;
  const auto* textures = ctx.textures();
  auto it = textures ? textures->find(name) : decltype(textures->end()){};
  if (!textures || it == textures->end()) {
    std::vector<std::string> names;
    if (textures)
      for (const auto& t : *textures) names.push_back(t.first);
    const std::string hint = closest(name, names);
    ctx.fail(name_node.path, "no texture named \"" + name + "\" in the textures section" +
                                 (hint.empty() ? std::string() : " (did you mean \"" + hint + "\"?)"));
  }
  r.texture = it->second;
  r.channel = -1;
  const Node ch = child(n, "channel");
  if (ch.j) {
    std::vector<std::pair<std::string, int>> values = {{"r", 0}, {"g", 1}, {"b", 2}, {"a", 3}};
    values.push_back(colour ? std::make_pair(std::string("rgb"), -1) : std::make_pair(std::string("luminance"), -1));
    r.channel = read_enum<int>(ctx, ch, values);
  }
  const Node mul = child(n, "multiplier");
  if (mul.j) r.multiplier = static_cast<float>(read_number(ctx, mul));
  const Node off = child(n, "offset");
  if (off.j) r.offset = static_cast<float>(read_number(ctx, off));
  if (!std::isfinite(r.multiplier) || !std::isfinite(r.offset))
    ctx.fail(n.path, "multiplier and offset must be finite numbers");
  const Node set = child(n, "uv_set");
  if (set.j) r.uv_set = read_int_in(ctx, set, 0, 1);
  return r;
}

glm::dvec3 read_colour(const LoadContext& ctx, const Node& n) {
  if (is_texture_reference(*n.j)) fail_texture(ctx, n);
  if (n.j->is_number()) return glm::dvec3(read_number(ctx, n));
  if (n.j->is_array() && n.j->size() == 3) return read_vec3(ctx, n);
  ctx.fail(n.path,
           "expected a colour ([r, g, b] or a single number for grey), got " + describe(*n.j));
}

double read_scalar_input(const LoadContext& ctx, const Node& n) {
  if (is_texture_reference(*n.j)) fail_texture(ctx, n);
  return read_number(ctx, n);
}

bool Range::contains(double v) const {
  const bool above = lo_open ? v > lo : v >= lo;
  const bool below = hi_open ? v < hi : v <= hi;
  return above && below;
}

std::string Range::describe() const {
  if (std::isinf(hi)) return (lo_open ? "> " : ">= ") + format_number(lo);
  return std::string("in ") + (lo_open ? "(" : "[") + format_number(lo) + ", " + format_number(hi) +
         (hi_open ? ")" : "]");
}

double read_number_in(const LoadContext& ctx, const Node& n, const Range& r) {
  const double v = read_number(ctx, n);
  if (!r.contains(v)) ctx.fail(n.path, "must be " + r.describe() + ", got " + describe(*n.j));
  return v;
}

int read_int_in(const LoadContext& ctx, const Node& n, int64_t lo, int64_t hi) {
  const int64_t v = read_integer(ctx, n);
  if (v < lo || v > hi) {
    const std::string range = hi >= std::numeric_limits<int>::max()
                                  ? ">= " + std::to_string(lo)
                                  : "between " + std::to_string(lo) + " and " + std::to_string(hi);
    ctx.fail(n.path, "must be " + range + ", got " + describe(*n.j));
  }
  return static_cast<int>(v);
}

}  // namespace scene_detail
}  // namespace aw
