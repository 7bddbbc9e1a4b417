// The strict JSON parser and ObjectReader: every error names the file and the key or the
// line:column.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include "scene/json_strict.hpp"

namespace fracref {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

/// The message of the InputError `f` throws ("" and a test failure when it throws none).
template <class F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError thrown";
  return "";
}

std::string parse_error(const std::string& text) {
  return input_error([&] { parse_json_strict(text, "s.json"); });
}

json parse(const std::string& text) { return parse_json_strict(text, "s.json"); }

TEST(ParseJsonStrict, ParsesAValidDocument) {
  const json j = parse(R"({"a": 1, "b": [true, null, "x"], "c": {"d": -2.5, "e": 18446744073709551615}})");
  EXPECT_EQ(j["a"].get<int>(), 1);
  EXPECT_EQ(j["b"].size(), 3u);
  EXPECT_TRUE(j["b"][0].get<bool>());
  EXPECT_TRUE(j["b"][1].is_null());
  EXPECT_EQ(j["b"][2].get<std::string>(), "x");
  EXPECT_DOUBLE_EQ(j["c"]["d"].get<double>(), -2.5);
  EXPECT_EQ(j["c"]["e"].get<std::uint64_t>(), 18446744073709551615ull);
  EXPECT_EQ(parse("[1, 2]").size(), 2u);
}

TEST(ParseJsonStrict, SameKeysInDifferentObjectsAreNotDuplicates) {
  const json j = parse(R"({"a": {"x": 1}, "b": {"x": 2}, "l": [{"x": 3}, {"x": 4}]})");
  EXPECT_EQ(j["b"]["x"].get<int>(), 2);
  EXPECT_EQ(j["l"][1]["x"].get<int>(), 4);
}

TEST(ParseJsonStrict, SyntaxErrorNamesLineAndColumn) {
  EXPECT_EQ(parse_error("{\n  \"a\": 1,\n  \"b\": 2,\n}"),
            "s.json:4:1: syntax error while parsing object key - unexpected '}'; expected string literal");
  EXPECT_EQ(parse_error("{\"a\": 1}\n x").rfind("s.json:2:2: syntax error", 0), 0u);
  EXPECT_EQ(parse_error("{\n  \"a\": 1,\n  \"b\": tru\n}").rfind("s.json:3:11: syntax error", 0), 0u);
}

TEST(ParseJsonStrict, EndOfInputIsLocatedAfterTheLastByte) {
  EXPECT_EQ(parse_error("{\n\"a\": [1,\n2").rfind("s.json:3:2: syntax error while parsing array - unexpected end", 0), 0u);
  EXPECT_EQ(parse_error("{\"a\": 1,\n").rfind("s.json:2:1: ", 0), 0u);
}

TEST(ParseJsonStrict, EmptyInputIsAnError) {
  EXPECT_EQ(parse_error(""), "s.json: the file is empty (expected a JSON object)");
  EXPECT_EQ(parse_error(" \n\t"), "s.json: the file is empty (expected a JSON object)");
}

TEST(ParseJsonStrict, DuplicateKeyNamesItsPath) {
  EXPECT_EQ(parse_error(R"({"a": 1, "a": 2})"), "s.json: key 'a': duplicate key (a key may appear only once per object)");
  EXPECT_EQ(parse_error(R"({"refine": {"tau": 1, "delta": 2, "tau": 1}})").rfind("s.json: key 'refine.tau': duplicate key", 0),
            0u);
  EXPECT_EQ(parse_error(R"({"r": {"x": [[1], [2, {"q": 1, "q": 1}]]}})").rfind("s.json: key 'r.x[1][1].q': duplicate", 0),
            0u);
  // Duplicates of a whole sub-object count too.
  EXPECT_EQ(parse_error(R"({"field": {}, "field": {}})").rfind("s.json: key 'field': duplicate", 0), 0u);
}

TEST(ParseJsonStrict, NumberOverflowNamesKeyAndPosition) {
  EXPECT_EQ(parse_error("{\n  \"refine\": {\"tau\": 1e999}}"),
            "s.json:2:21: key 'refine.tau': number overflow parsing '1e999' (too large for a double)");
  EXPECT_EQ(parse_error(R"({"r": [1, -1e999]})").rfind("s.json:1:11: key 'r[1]': number overflow", 0), 0u);
}

TEST(ParseJsonStrict, InvalidUtf8IsAnError) {
  EXPECT_EQ(parse_error("{\"a\": \"\xff\"}").rfind("s.json:1:8: syntax error while parsing value - invalid string", 0), 0u);
}

class TempDir : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("fracref_scene_json_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
    return dir_ / name;
  }
  fs::path dir_;
};

using ReadJsonFile = TempDir;

TEST_F(ReadJsonFile, ReadsAFile) {
  EXPECT_EQ(read_json_file(write("a.json", R"({"k": [1, 2, 3]})"))["k"].size(), 3u);
}

TEST_F(ReadJsonFile, MissingFileAndFolderAreNamed) {
  const fs::path missing = dir_ / "missing.json";
  EXPECT_EQ(input_error([&] { read_json_file(missing); }), missing.string() + ": file not found");
  EXPECT_EQ(input_error([&] { read_json_file(dir_); }), dir_.string() + ": is a folder, expected a JSON file");
}

TEST_F(ReadJsonFile, SyntaxErrorNamesTheFileAsGiven) {
  const fs::path p = write("bad.json", "{\n  \"a\": ,\n}");
  EXPECT_EQ(input_error([&] { read_json_file(p); }).rfind(p.string() + ":2:8: syntax error", 0), 0u);
}

// ------------------------------------------------------------------------------------------
// ObjectReader

std::string reader_error(const std::string& text, const std::function<void(ObjectReader&)>& read) {
  const json j = parse(text);
  return input_error([&] {
    ObjectReader r(j, "s.json", "refine");
    read(r);
  });
}

TEST(ObjectReader, ReadsEveryTypeAndAppliesDefaults) {
  const json j = parse(R"({"n": 2.5, "i": 7, "b": false, "s": "hi", "c": "wood", "v": [1, 2.5, -3],
                           "u": [2, 3, 4], "l": [0.5, 1], "o": {"x": 1}})");
  ObjectReader r(j, "s.json", "");
  EXPECT_DOUBLE_EQ(r.number("n", 0.0), 2.5);
  EXPECT_DOUBLE_EQ(r.number("absent", 4.25), 4.25);
  EXPECT_DOUBLE_EQ(r.number_required("i"), 7.0);  // an integer is a number
  EXPECT_EQ(r.integer("i", 0), 7);
  EXPECT_EQ(r.integer("absent_i", -3), -3);
  EXPECT_FALSE(r.boolean("b", true));
  EXPECT_TRUE(r.boolean("absent_b", true));
  EXPECT_EQ(r.string("s", ""), "hi");
  EXPECT_EQ(r.choice("c", {"marble", "wood"}, "marble"), "wood");
  EXPECT_EQ(r.choice("absent_c", {"marble", "wood"}, "marble"), "marble");
  EXPECT_EQ(r.vec3_required("v"), glm::dvec3(1, 2.5, -3));
  EXPECT_EQ(r.uvec3_required("u", {2, 1024}), glm::uvec3(2, 3, 4));
  EXPECT_EQ(r.uvec3("absent_u", glm::uvec3(9), {2, 1024}), glm::uvec3(9));
  EXPECT_EQ(r.numbers_required("l", 0), (std::vector<double>{0.5, 1.0}));
  std::optional<ObjectReader> o = r.object("o");
  ASSERT_TRUE(o.has_value());
  EXPECT_EQ(o->object_path(), "o");
  EXPECT_EQ(o->integer_required("x"), 1);
  o->finish();
  EXPECT_FALSE(r.object("absent_o").has_value());
  r.finish();
}

TEST(ObjectReader, IntegralFloatsAreIntegers) {
  const json j = parse(R"({"a": 5.0, "b": 1e3, "c": -0.0})");
  ObjectReader r(j, "s.json", "");
  EXPECT_EQ(r.integer_required("a"), 5);
  EXPECT_EQ(r.integer_required("b"), 1000);
  EXPECT_EQ(r.integer_required("c"), 0);
}

TEST(ObjectReader, UnknownKeyIsNamedWithSuggestionAndAllowedKeys) {
  EXPECT_EQ(reader_error(R"({"tau": 1, "dleta": 2})",
                         [](ObjectReader& r) {
                           r.number("tau", 0.1);
                           r.number("delta", 0.1);
                           r.finish();
                         }),
            "s.json: key 'refine.dleta': unknown key (did you mean 'delta'?); allowed keys: 'tau', 'delta'");
  EXPECT_EQ(reader_error(R"({"zzz": 1})", [](ObjectReader& r) { r.finish(); }),
            "s.json: key 'refine.zzz': unknown key; this object takes no keys");
}

TEST(ObjectReader, MissingRequiredKeyIsNamed) {
  EXPECT_EQ(reader_error("{}", [](ObjectReader& r) { r.number_required("tau"); }),
            "s.json: key 'refine.tau': required key is missing");
  EXPECT_EQ(reader_error(R"({"tua": 1})", [](ObjectReader& r) { r.number_required("tau"); }),
            "s.json: key 'refine.tau': required key is missing (is 'tua' a misspelling of it?)");
}

TEST(ObjectReader, WrongTypesAreNamed) {
  EXPECT_EQ(reader_error(R"({"tau": "NaN"})", [](ObjectReader& r) { r.number("tau", 1); }),
            "s.json: key 'refine.tau': expected a number, got string \"NaN\" (JSON numbers cannot be NaN or infinite)");
  EXPECT_EQ(reader_error(R"({"tau": "-Infinity"})", [](ObjectReader& r) { r.number("tau", 1); }),
            "s.json: key 'refine.tau': expected a number, got string \"-Infinity\" (JSON numbers cannot be NaN or "
            "infinite)");
  EXPECT_EQ(reader_error(R"({"tau": "0.1"})", [](ObjectReader& r) { r.number("tau", 1); }),
            "s.json: key 'refine.tau': expected a number, got string \"0.1\" (write the number without quotes)");
  EXPECT_EQ(reader_error(R"({"tau": null})", [](ObjectReader& r) { r.number("tau", 1); }),
            "s.json: key 'refine.tau': expected a number, got null");
  EXPECT_EQ(reader_error(R"({"on": 1})", [](ObjectReader& r) { r.boolean("on", true); }),
            "s.json: key 'refine.on': expected true or false, got 1");
  EXPECT_EQ(reader_error(R"({"s": 1})", [](ObjectReader& r) { r.string("s", ""); }),
            "s.json: key 'refine.s': expected a string, got 1");
  EXPECT_EQ(reader_error(R"({"o": [1]})", [](ObjectReader& r) { r.object("o"); }),
            "s.json: key 'refine.o': expected an object, got an array");
  EXPECT_EQ(reader_error(R"({"o": 3})", [](ObjectReader& r) { r.raw_object("o"); }),
            "s.json: key 'refine.o': expected an object, got 3");
}

TEST(ObjectReader, TopLevelMustBeAnObject) {
  const json j = parse("[1]");
  EXPECT_EQ(input_error([&] { ObjectReader(j, "s.json", ""); }),
            "s.json: the top level must be a JSON object, got an array");
}

TEST(ObjectReader, NonIntegersAreRejected) {
  EXPECT_EQ(reader_error(R"({"n": 2.5})", [](ObjectReader& r) { r.integer("n", 1); }),
            "s.json: key 'refine.n': expected an integer, got 2.5");
  EXPECT_EQ(reader_error(R"({"n": 9223372036854775808})", [](ObjectReader& r) { r.integer("n", 1); }),
            "s.json: key 'refine.n': integer out of range, got 9223372036854775808");
  EXPECT_EQ(reader_error(R"({"n": 1e300})", [](ObjectReader& r) { r.integer("n", 1); }),
            "s.json: key 'refine.n': integer out of range, got 1e+300");
  EXPECT_EQ(reader_error(R"({"n": "3"})", [](ObjectReader& r) { r.integer("n", 1); }),
            "s.json: key 'refine.n': expected an integer, got string \"3\" (write the number without quotes)");
}

TEST(ObjectReader, RangesAreEnforcedAndDescribed) {
  EXPECT_EQ(reader_error(R"({"tau": -1})", [](ObjectReader& r) { r.number("tau", 1, Range::greater_than(0)); }),
            "s.json: key 'refine.tau': must be > 0, got -1");
  EXPECT_EQ(reader_error(R"({"tau": 0})", [](ObjectReader& r) { r.number("tau", 1, Range::greater_than(0)); }),
            "s.json: key 'refine.tau': must be > 0, got 0");
  EXPECT_EQ(reader_error(R"({"a": 60})", [](ObjectReader& r) { r.number("a", 1, Range::half_open(0, 60)); }),
            "s.json: key 'refine.a': must be in [0, 60), got 60");
  EXPECT_EQ(reader_error(R"({"t": 1e308})", [](ObjectReader& r) { r.number("t", 0.5, Range::open(0, 1)); }),
            "s.json: key 'refine.t': must be in (0, 1), got 1e+308");
  EXPECT_EQ(reader_error(R"({"p": -0.5})", [](ObjectReader& r) { r.number("p", 1, Range::at_least(0)); }),
            "s.json: key 'refine.p': must be >= 0, got -0.5");
  EXPECT_EQ(reader_error(R"({"l": 9})", [](ObjectReader& r) { r.integer("l", 1, {1, 8}); }),
            "s.json: key 'refine.l': must be an integer in [1, 8], got 9");
  EXPECT_EQ(reader_error(R"({"s": -1})", [](ObjectReader& r) { r.integer("s", 1, IntRange::at_least(0)); }),
            "s.json: key 'refine.s': must be an integer >= 0, got -1");
  // Boundaries of closed and open ends.
  const json j = parse(R"({"a": 0, "b": 8, "c": 1})");
  ObjectReader r(j, "s.json", "");
  EXPECT_DOUBLE_EQ(r.number("a", 1, Range::half_open(0, 60)), 0.0);
  EXPECT_EQ(r.integer("b", 1, {1, 8}), 8);
  EXPECT_DOUBLE_EQ(r.number("c", 0, Range{0, 1, true, false}), 1.0);
}

TEST(ObjectReader, ArrayElementsAreNamedByIndex) {
  EXPECT_EQ(reader_error(R"({"res": [50, 50.5, 50]})", [](ObjectReader& r) { r.uvec3_required("res", {2, 1024}); }),
            "s.json: key 'refine.res[1]': expected an integer, got 50.5");
  EXPECT_EQ(reader_error(R"({"res": [50, 50, 1]})", [](ObjectReader& r) { r.uvec3_required("res", {2, 1024}); }),
            "s.json: key 'refine.res[2]': must be an integer in [2, 1024], got 1");
  EXPECT_EQ(reader_error(R"({"res": [50, 50]})", [](ObjectReader& r) { r.uvec3_required("res", {2, 1024}); }),
            "s.json: key 'refine.res': expected an array of 3 elements, got 2");
  EXPECT_EQ(reader_error(R"({"res": 50})", [](ObjectReader& r) { r.uvec3_required("res", {2, 1024}); }),
            "s.json: key 'refine.res': expected an array, got 50");
  EXPECT_EQ(reader_error(R"({"v": [0, "x", 0]})", [](ObjectReader& r) { r.vec3_required("v"); }),
            "s.json: key 'refine.v[1]': expected a number, got string \"x\"");
  EXPECT_EQ(reader_error(R"({"l": []})", [](ObjectReader& r) { r.numbers_required("l", 0); }),
            "s.json: key 'refine.l': the array must not be empty");
}

TEST(ObjectReader, ChoiceListsAllowedValues) {
  EXPECT_EQ(reader_error(R"({"kind": "tet"})", [](ObjectReader& r) { r.choice_required("kind", {"tets", "pieces"}); }),
            "s.json: key 'refine.kind': must be one of 'tets', 'pieces', got 'tet' (did you mean 'tets'?)");
}

TEST(ObjectReader, PathsResolveAgainstTheBaseFolder) {
  const json j = parse(R"({"rel": "sub/../m.obj", "abs": "/x/./y.obj", "list": ["a.obj", "../b.obj"], "e": ""})");
  ObjectReader r(j, "s.json", "");
  EXPECT_EQ(r.path("rel", "/base/dir"), fs::path("/base/dir/m.obj"));
  EXPECT_EQ(r.path_required("abs", "/base/dir"), fs::path("/x/y.obj"));
  EXPECT_EQ(r.path("absent", "/base"), fs::path());
  EXPECT_EQ(r.paths_required("list", "/base/dir"), (std::vector<fs::path>{"/base/dir/a.obj", "/base/b.obj"}));
  EXPECT_EQ(input_error([&] { r.path("e", "/base"); }), "s.json: key 'e': the path must not be empty");
}

TEST(ObjectReader, ForbidRejectsOnlyPresentKeys) {
  EXPECT_EQ(reader_error(R"({"file": "a.raw"})", [](ObjectReader& r) { r.forbid("file", "only for grids"); }),
            "s.json: key 'refine.file': only for grids");
  const json j = parse("{}");
  ObjectReader r(j, "s.json", "");
  r.forbid("file", "only for grids");
  r.finish();
}

TEST(ObjectReader, HasMarksKeyAsKnown) {
  const json j = parse(R"({"x": 1})");
  ObjectReader r(j, "s.json", "");
  EXPECT_THROW(r.finish(), InputError);
  EXPECT_TRUE(r.has("x"));
  EXPECT_NO_THROW(r.finish());
}

TEST(ObjectReader, RawObjectIsReturnedUnvalidated) {
  const json j = parse(R"({"params": {"veins": 3, "anything": [1]}})");
  ObjectReader r(j, "s.json", "field");
  const json p = r.raw_object("params");
  EXPECT_EQ(p["veins"].get<int>(), 3);
  EXPECT_TRUE(r.raw_object("absent").is_object());
  EXPECT_TRUE(r.raw_object("absent").empty());
  r.finish();
  // A room validates it later with its own reader and prefix.
  ObjectReader params(p, "s.json", "field.params");
  params.integer("veins", 1);
  EXPECT_EQ(input_error([&] { params.finish(); }).rfind("s.json: key 'field.params.anything': unknown key", 0), 0u);
}

TEST(RangeDescribe, Texts) {
  EXPECT_EQ(Range{}.describe(), "");
  EXPECT_EQ(Range::closed(0.5, 2).describe(), "must be in [0.5, 2]");
  EXPECT_EQ((Range{0, 1, true, true}).describe(), "must be in (0, 1)");
  EXPECT_EQ((Range{-std::numeric_limits<double>::infinity(), 3, false, true}).describe(), "must be < 3");
  EXPECT_EQ(IntRange{}.describe(), "");
}

}  // namespace
}  // namespace fracref

// Deep nesting is an error naming the key, not a stack overflow in the code that walks the
// document (100,000 nested arrays overflowed the message that printed the wrong-typed value).
TEST(StrictJson, DeepNestingIsAnError) {
  const std::string deep = "{\"exterior\": " + std::string(100000, '[') + std::string(100000, ']') + "}";
  try {
    fracref::parse_json_strict(deep, "s.json");
    FAIL() << "accepted";
  } catch (const fracref::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("s.json: key 'exterior[0][0]", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("nested deeper than 64 levels"), std::string::npos) << e.what();
  }
  std::string ok = "{\"a\": " + std::string(60, '[') + std::string(60, ']') + "}";
  EXPECT_NO_THROW(fracref::parse_json_strict(ok, "s.json"));
}
