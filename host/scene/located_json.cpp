#include "host/scene/located_json.h"

#include <algorithm>
#include <iterator>
#include <utility>

namespace aw {
namespace scene_detail {

std::string join_key(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string join_index(const std::string& parent, size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

std::string parent_path(const std::string& path) {
  const size_t cut = path.find_last_of(".[");
  return cut == std::string::npos ? std::string() : path.substr(0, cut);
}

LineMap::LineMap(const std::string* text) : text_(text) {
  line_starts_.push_back(0);
  for (size_t i = 0; i < text->size(); ++i) {
    if ((*text)[i] == '\n') line_starts_.push_back(i + 1);
  }
}

TextPos LineMap::at(size_t offset) const {
  offset = std::min(offset, text_->size());
  // The last line start <= offset.
  const auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), offset) - 1;
  TextPos pos;
  pos.line = static_cast<int>(it - line_starts_.begin()) + 1;
  int col = 1;
  for (size_t i = *it; i < offset; ++i) {
    // UTF-8 continuation bytes (10xxxxxx) do not start a new character.
    if ((static_cast<unsigned char>((*text_)[i]) & 0xC0) != 0x80) ++col;
  }
  pos.col = col;
  return pos;
}

namespace {

// An iterator over the text that publishes how far nlohmann's lexer has read. nlohmann's
// iterator_input_adapter only copies, dereferences, advances and compares it, so a forward
// iterator over a char buffer is all it needs.
class CountingIterator {
 public:
  using iterator_category = std::forward_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  CountingIterator(const char* p, const char* base, size_t* consumed)
      : p_(p), base_(base), consumed_(consumed) {}

  reference operator*() const { return *p_; }
  CountingIterator& operator++() {
    ++p_;
    *consumed_ = static_cast<size_t>(p_ - base_);
    return *this;
  }
  CountingIterator operator++(int) {
    CountingIterator old = *this;
    ++*this;
    return old;
  }
  bool operator==(const CountingIterator& o) const { return p_ == o.p_; }
  bool operator!=(const CountingIterator& o) const { return p_ != o.p_; }

 private:
  const char* p_;
  const char* base_;
  size_t* consumed_;
};

bool is_number_char(char c) {
  return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' || c == 'e' || c == 'E';
}

// Builds an ordered_json DOM from SAX events (what nlohmann's json_sax_dom_parser does) and
// records positions. Values are built bottom-up on an owning stack, so no pointer into a
// growing container is ever held.
class LocatingBuilder {
 public:
  using number_integer_t = Json::number_integer_t;
  using number_unsigned_t = Json::number_unsigned_t;
  using number_float_t = Json::number_float_t;
  using string_t = Json::string_t;
  using binary_t = Json::binary_t;

  LocatingBuilder(const std::string& text, const size_t* consumed, LocatedJson* out)
      : text_(text), consumed_(consumed), out_(out) {}

  // --- SAX interface ----------------------------------------------------------------------
  bool null() { return scalar(Json(nullptr), literal_start(4)); }
  bool boolean(bool v) { return scalar(Json(v), literal_start(v ? 4 : 5)); }
  bool number_integer(number_integer_t v) { return scalar(Json(v), number_start()); }
  bool number_unsigned(number_unsigned_t v) { return scalar(Json(v), number_start()); }
  bool number_float(number_float_t v, const string_t&) { return scalar(Json(v), number_start()); }
  bool string(string_t& v) { return scalar(Json(std::move(v)), string_start()); }
  bool binary(binary_t&) { return true; }  // never produced by the JSON (text) format

  bool start_object(std::size_t) { return open(Json::object(), *consumed_ - 1); }
  bool start_array(std::size_t) { return open(Json::array(), *consumed_ - 1); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }

  bool key(string_t& k) {
    Frame& f = stack_.back();
    const size_t start = string_start();
    if (f.value.contains(k)) {
      // nlohmann would silently keep the last one; a repeated key is almost always an edit
      // mistake, and silently dropping half of it is exactly what the format forbids.
      error_offset_ = start;
      error_message_ = join_key(f.path, k) + ": duplicate key \"" + k + "\"";
      return false;
    }
    f.key = k;
    out_->locs[join_key(f.path, k)].key = start;
    return true;
  }

  bool parse_error(std::size_t position, const std::string& /*last_token*/,
                   const nlohmann::detail::exception& ex) {
    error_message_ = strip_nlohmann_message(ex.what());
    error_offset_ = error_token_start(position);
    return false;
  }

  size_t error_offset() const { return error_offset_; }
  const std::string& error_message() const { return error_message_; }

 private:
  struct Frame {
    Json value;
    std::string path;
    std::string key;  // pending member name (objects)
  };

  // "[json.exception.parse_error.101] parse error at line 1, column 5: syntax error ..." ->
  // "syntax error ...": we print our own position in front. The "; last read: '...'" tail
  // goes too: nlohmann's token buffer is only reset at strings and numbers, so after a
  // literal or punctuation it shows unrelated text ("last read: '"width": tru '").
  static std::string strip_nlohmann_message(const std::string& what) {
    std::string s = what;
    if (!s.empty() && s[0] == '[') {
      const size_t close = s.find("] ");
      if (close != std::string::npos) s = s.substr(close + 2);
    }
    if (s.compare(0, 12, "parse error ") == 0) {
      const size_t colon = s.find(": ");
      if (colon != std::string::npos) s = s.substr(colon + 2);
    }
    const size_t tail = s.find("; last read: ");
    if (tail != std::string::npos) s = s.substr(0, tail);
    return s;
  }

  // nlohmann reports the number of characters read, i.e. the position just after the
  // character that made the parse fail. Point at the start of the offending token instead,
  // which is where a user looks: the opening quote of an unexpected string, the first letter
  // of a bad literal ("tru"), the first character of a number that overflowed.
  size_t error_token_start(size_t position) const {
    if (position == 0) return 0;
    size_t p = position - 1;
    if (p >= text_.size()) {
      // End of input: point just after the last meaningful character rather than past
      // trailing newlines, so the position is on a line the user can see.
      p = text_.size();
      while (p > 0 && std::string(" \t\r\n").find(text_[p - 1]) != std::string::npos) --p;
      return p;
    }
    const std::string& m = error_message_;
    const auto is_alpha = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
    if (text_[p] == '"' && m.find("unexpected string literal") != std::string::npos) {
      return string_start_before(p + 1);
    }
    if (m.find("invalid literal") != std::string::npos) {
      if (!is_alpha(text_[p]) && p > 0 && is_alpha(text_[p - 1])) --p;
      while (p > 0 && is_alpha(text_[p - 1])) --p;
      return p;
    }
    if (is_number_char(text_[p])) {
      while (p > 0 && is_number_char(text_[p - 1])) --p;
    }
    return p;
  }

  // Start offsets of the token that was just lexed. The lexer has consumed the token and,
  // for numbers only, possibly one character of look-ahead (it "ungets" it internally but our
  // iterator has already moved past it).
  size_t literal_start(size_t len) const { return *consumed_ - len; }

  size_t number_start() const {
    size_t p = *consumed_;
    if (p > 0 && !is_number_char(text_[p - 1])) --p;  // the look-ahead character
    while (p > 0 && is_number_char(text_[p - 1])) --p;
    return p;
  }

  size_t string_start() const { return string_start_before(*consumed_); }

  // `end` is one past a string's closing quote. Walk back to the first quote that is
  // not escaped (preceded by an even number of backslashes): inside a JSON string every
  // literal quote is escaped, so that is the opening one.
  size_t string_start_before(size_t end) const {
    size_t p = end - 1;
    while (p > 0) {
      --p;
      if (text_[p] != '"') continue;
      size_t backslashes = 0;
      while (p >= backslashes + 1 && text_[p - backslashes - 1] == '\\') ++backslashes;
      if (backslashes % 2 == 0) return p;
    }
    return p;
  }

  // Records the position of a value that starts at `start` and returns its path.
  std::string locate_value(size_t start) {
    if (stack_.empty()) {
      out_->locs[""] = JsonLoc{start, start};
      return "";
    }
    Frame& f = stack_.back();
    if (f.value.is_object()) {
      std::string path = join_key(f.path, f.key);
      out_->locs[path].value = start;
      return path;
    }
    std::string path = join_index(f.path, f.value.size());
    out_->locs[path] = JsonLoc{start, start};
    return path;
  }

  void insert(Json v) {
    if (stack_.empty()) {
      out_->root = std::move(v);
      return;
    }
    Frame& f = stack_.back();
    if (f.value.is_object()) {
      f.value[f.key] = std::move(v);
    } else {
      f.value.push_back(std::move(v));
    }
  }

  bool scalar(Json v, size_t start) {
    locate_value(start);
    insert(std::move(v));
    return true;
  }

  bool open(Json container, size_t start) {
    // A scene nests a handful of levels. Without a limit, a file nested 20,000 deep took 5.5 s
    // to refuse (every level's path repeats its parent's, so the paths alone are quadratic in
    // the depth) and the message's dump of the offending value recursed once per level (a
    // stack overflow under AddressSanitizer at 5,000). Refused at the first bracket too deep.
    if (stack_.size() >= kMaxJsonDepth) {
      error_offset_ = start;
      error_message_ = "nested deeper than " + std::to_string(kMaxJsonDepth) +
                       " levels of objects and arrays (a scene needs fewer than 10)";
      return false;
    }
    std::string path = locate_value(start);
    stack_.push_back(Frame{std::move(container), std::move(path), std::string()});
    return true;
  }

  bool close() {
    Json v = std::move(stack_.back().value);
    stack_.pop_back();
    insert(std::move(v));
    return true;
  }

  const std::string& text_;
  const size_t* consumed_;
  LocatedJson* out_;
  std::vector<Frame> stack_;
  size_t error_offset_ = 0;
  std::string error_message_;
};

}  // namespace

bool parse_located_json(const std::string& text, LocatedJson* out, JsonSyntaxError* err) {
  *out = LocatedJson();
  size_t consumed = 0;
  const char* base = text.data();
  CountingIterator first(base, base, &consumed);
  CountingIterator last(base + text.size(), base, &consumed);
  LocatingBuilder builder(text, &consumed, out);
  // strict = true: trailing garbage after the root value is an error. No comments: the
  // format is plain JSON.
  const bool ok = Json::sax_parse(first, last, &builder, nlohmann::detail::input_format_t::json,
                                  /*strict=*/true, /*ignore_comments=*/false);
  if (!ok) {
    err->offset = builder.error_offset();
    err->message = builder.error_message();
    *out = LocatedJson();
  }
  return ok;
}

}  // namespace scene_detail
}  // namespace aw
