// The position-recording JSON parser (private to host/scene) on its own.
#include "host/scene/located_json.h"

#include <gtest/gtest.h>

namespace {

using aw::scene_detail::JsonSyntaxError;
using aw::scene_detail::LineMap;
using aw::scene_detail::LocatedJson;
using aw::scene_detail::parse_located_json;

std::string pos_of(const std::string& text, size_t offset) {
  const auto p = LineMap(&text).at(offset);
  return std::to_string(p.line) + ":" + std::to_string(p.col);
}

TEST(LocatedJson, KeyAndValuePositions) {
  const std::string text =
      "{\n"
      "  \"a\": 12,\n"
      "  \"b\": { \"c\": [true, -3.5e2, \"x\"], \"d\": null },\n"
      "  \"e\": 7}";
  LocatedJson doc;
  JsonSyntaxError err;
  ASSERT_TRUE(parse_located_json(text, &doc, &err)) << err.message;
  EXPECT_EQ(doc.root["b"]["c"][1].get<double>(), -350.0);
  EXPECT_EQ(pos_of(text, doc.locs.at("a").key), "2:3");
  EXPECT_EQ(pos_of(text, doc.locs.at("a").value), "2:8");
  EXPECT_EQ(pos_of(text, doc.locs.at("b").key), "3:3");
  EXPECT_EQ(pos_of(text, doc.locs.at("b").value), "3:8");
  EXPECT_EQ(pos_of(text, doc.locs.at("b.c").key), "3:10");
  EXPECT_EQ(pos_of(text, doc.locs.at("b.c[0]").key), "3:16");
  EXPECT_EQ(pos_of(text, doc.locs.at("b.c[1]").value), "3:22");  // number followed by ','
  EXPECT_EQ(pos_of(text, doc.locs.at("b.c[2]").value), "3:30");
  EXPECT_EQ(pos_of(text, doc.locs.at("b.d").value), "3:41");
  // A number directly followed by '}' and then the end of input.
  EXPECT_EQ(pos_of(text, doc.locs.at("e").value), "4:8");
  EXPECT_EQ(pos_of(text, doc.locs.at("").key), "1:1");
}

TEST(LocatedJson, KeepsFileOrder) {
  const std::string text = R"({"z": 1, "a": 2, "m": 3})";
  LocatedJson doc;
  JsonSyntaxError err;
  ASSERT_TRUE(parse_located_json(text, &doc, &err));
  std::string order;
  for (const auto& item : doc.root.items()) order += item.key();
  EXPECT_EQ(order, "zam");
}

TEST(LocatedJson, SyntaxErrorsPointAtTheOffendingToken) {
  struct Case {
    std::string text, expected_pos, fragment;
  };
  const Case cases[] = {
      {"{\"a\": tru}", "1:7", "invalid literal"},
      {"{\"a\": 1 \"b\": 2}", "1:9", "unexpected string literal"},
      {"{\"a\": 1,, }", "1:9", "unexpected ','"},
      // End of input: just after the last character, not on the empty lines after it.
      {"{\"a\":\n  [1, 2\n\n", "2:8", "unexpected end of input"},
      {"{\"a\": 1e999}", "1:7", "number overflow"},
      {"{\"a\": 1} \"x\"", "1:10", "expected end of input"},
  };
  for (const Case& c : cases) {
    LocatedJson doc;
    JsonSyntaxError err;
    ASSERT_FALSE(parse_located_json(c.text, &doc, &err)) << c.text;
    EXPECT_EQ(pos_of(c.text, err.offset), c.expected_pos) << c.text << " -> " << err.message;
    EXPECT_NE(err.message.find(c.fragment), std::string::npos) << err.message;
    // Our own position replaces nlohmann's prefix.
    EXPECT_EQ(err.message.find("[json.exception"), std::string::npos) << err.message;
  }
}

TEST(LocatedJson, DuplicateKeysAreErrors) {
  const std::string text = "{\"a\": 1,\n \"a\": 2}";
  LocatedJson doc;
  JsonSyntaxError err;
  ASSERT_FALSE(parse_located_json(text, &doc, &err));
  EXPECT_EQ(pos_of(text, err.offset), "2:2");
  EXPECT_NE(err.message.find("duplicate key \"a\""), std::string::npos);
}

// Nesting is limited (kMaxJsonDepth): the limit itself parses, one level more is refused at
// that level's bracket, and so is a hostile file 100,000 levels deep (objects and arrays),
// without building the deep paths (which made 20,000 levels take seconds) or recursing.
TEST(LocatedJson, DeepNestingIsRefusedAtTheLimit) {
  const size_t limit = aw::scene_detail::kMaxJsonDepth;
  auto arrays = [](size_t n) { return std::string(n, '[') + std::string(n, ']'); };
  LocatedJson doc;
  JsonSyntaxError err;
  EXPECT_TRUE(parse_located_json(arrays(limit), &doc, &err)) << err.message;
  ASSERT_FALSE(parse_located_json(arrays(limit + 1), &doc, &err));
  EXPECT_EQ(err.offset, limit);  // the bracket that opens level limit + 1
  EXPECT_NE(err.message.find("nested deeper than " + std::to_string(limit) + " levels"), std::string::npos)
      << err.message;
  ASSERT_FALSE(parse_located_json("{\"materials\": " + arrays(100000) + "}", &doc, &err));
  EXPECT_EQ(err.offset, 14u + limit - 1);  // after '{"materials": ' the root object is level 1
  std::string objects;
  for (int i = 0; i < 100000; ++i) objects += "{\"a\":";
  objects += "1" + std::string(100000, '}');
  ASSERT_FALSE(parse_located_json(objects, &doc, &err));
  EXPECT_NE(err.message.find("nested deeper"), std::string::npos) << err.message;
  EXPECT_EQ(err.offset, 5u * limit);
}

TEST(LineMapTest, ColumnsCountCharacters) {
  const std::string text = "ab\n\xC3\xA9x\ny";  // "é" is two bytes
  EXPECT_EQ(pos_of(text, 0), "1:1");
  EXPECT_EQ(pos_of(text, 2), "1:3");
  EXPECT_EQ(pos_of(text, 3), "2:1");
  EXPECT_EQ(pos_of(text, 5), "2:2");  // 'x' after the two-byte character
  EXPECT_EQ(pos_of(text, 7), "3:1");
  EXPECT_EQ(pos_of(text, 100), "3:2");  // clamped to the end
}

}  // namespace
