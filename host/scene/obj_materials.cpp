// OBJ with Wavefront MTL materials (obj_materials.h). The OBJ is read with the same steps as
// load_obj (obj_read.h); the MTL files are read by the parser below and converted to the
// Architectural material. The mapping, with its reasons and what is approximated or ignored, is
// docs/obj-mtl.md. "MTL spec" below is the Wavefront MTL material format (Alias|Wavefront, 1995),
// the "Material Library File (.mtl)" chapter of the Advanced Visualizer manual; section names
// are its own ("Material color and illumination statements", "Texture map statements", ...).
// Pr, Pm, Ke, map_Ke, map_Pr, map_Pm and norm are not in it: they are the exporters' PBR
// extension of MTL (as tinyobjloader and Blender read and write it).
#include "host/scene/obj_materials.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "host/scene/obj_read.h"

namespace aw {
namespace scene_detail {
namespace {

namespace fs = std::filesystem;

// bump.scale for "-bm 1": the height, in scene units, of a bump map's full range (texel value 0
// to 1). MTL gives bump values no unit (MTL spec, "bump": "-bm mult_value ... multiplies the
// values stored in the bump map"), so archwave chooses one: 1 cm for scenes in metres, in the
// range of the scale the documentation's bump examples use (0.002 to 0.03).
constexpr double kMtlBumpUnit = 0.01;

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string fmt(const glm::dvec3& c) { return "[" + fmt(c.x) + ", " + fmt(c.y) + ", " + fmt(c.z) + "]"; }

double luminance(const glm::dvec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

// ---- the MTL text ---------------------------------------------------------------------------

// One texture map statement (map_Kd, bump, ...): the options before the file name and the file
// (MTL spec, "Texture map statements" and "Options for texture map statements").
struct MtlMap {
  bool present = false;
  std::string statement;  // as written: "map_Kd", "bump", ...
  std::string file;       // as written, relative to the folder of the .mtl
  size_t line = 0;
  glm::dvec2 scale{1.0}, offset{0.0};   // -s u [v [w]], -o u [v [w]] (w: no 3-D textures)
  bool clamp = false;                   // -clamp on
  std::optional<double> bm;             // -bm mult
  double mm_base = 0.0, mm_gain = 1.0;  // -mm base [gain]
  char imfchan = 0;                     // -imfchan r|g|b|m|l|z; 0 = not given
  std::vector<std::string> ignored;     // options without an archwave equivalent, as written
};

struct MtlMaterial {
  std::string name;
  std::string library;      // as the OBJ's mtllib names it, for messages
  std::string library_dir;  // the folder of the resolved .mtl: map files are relative to it
  std::optional<glm::dvec3> kd, ks, ke, tf;
  std::optional<double> ns, ni, d, tr, pr, pm;
  bool d_halo = false;
  int illum = -1;  // -1: no illum statement
  MtlMap map_kd, map_ks, map_ns, map_d, map_ke, map_pr, map_pm, bump, norm;
  std::vector<std::string> ignored;  // statements ignored with a warning, in order, once each
  void ignore(const std::string& statement) {
    if (std::find(ignored.begin(), ignored.end(), statement) == ignored.end()) ignored.push_back(statement);
  }
};

struct Token {
  std::string text;
  size_t begin = 0;  // position in the line
};

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::vector<Token> split_line(const std::string& line) {
  std::vector<Token> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_blank(line[i])) ++i;
    if (i == line.size()) break;
    const size_t b = i;
    while (i < line.size() && !is_blank(line[i])) ++i;
    out.push_back(Token{line.substr(b, i - b), b});
  }
  return out;
}

// Reads one .mtl file's text into materials. tinyobjloader's own MTL reader is not used: it
// turns a value that is not a number into 0 without a word (as it does for OBJ vertices,
// obj_mesh.cpp), reads "Kd 0.5" as (0.5, 0, 0) where the MTL spec's "Kd r g b" says g and b
// default to r, and loses the file of "map_Kd -s 2 file.png" (it takes "file.png" for the
// second number of -s). This parser is strict: every malformed statement is an error that names
// the line.
class MtlParser {
 public:
  // defined: the names defined so far, by this library and those read before it (a name keeps
  // its first definition), with where; shared by the parsers of one OBJ's libraries.
  MtlParser(std::string library, std::string library_dir, std::vector<MtlMaterial>* materials,
            std::map<std::string, std::string>* defined, std::vector<std::string>* warnings)
      : library_(std::move(library)),
        library_dir_(std::move(library_dir)),
        materials_(materials),
        defined_(defined),
        warnings_(warnings) {}

  bool parse(const std::string& text, std::string* error) {
    error_ = error;
    // A UTF-8 byte order mark (some Windows tools write one) is not part of the first statement.
    std::istringstream lines(text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? text.substr(3) : text);
    for (std::string line; std::getline(lines, line);) {
      ++line_;
      std::vector<Token> tok = split_line(line);
      if (tok.empty() || tok[0].text[0] == '#') continue;
      if (!statement(line, tok)) return false;
    }
    return true;
  }

 private:
  bool fail(const std::string& what) {
    *error_ = "material library \"" + library_ + "\", line " + std::to_string(line_) + ": " + what;
    return false;
  }

  void warn(const std::string& what) {
    warnings_->push_back("material library \"" + library_ + "\", line " + std::to_string(line_) + ": " + what);
  }

  bool number(const std::string& statement, const std::string& text, double* out) {
    if (!is_decimal_number(text)) {
      return fail("'" + statement + "' value \"" + text + "\" is not a finite decimal number");
    }
    *out = std::strtod(text.c_str(), nullptr);
    if (!std::isfinite(static_cast<float>(*out))) {
      return fail("'" + statement + "' value \"" + text + "\" is out of the range of float");
    }
    return true;
  }

  static std::string count(size_t n) { return n == 1 ? "1 value" : std::to_string(n) + " values"; }

  // "Kd r g b" (MTL spec, "Material color and illumination statements"): g and b are optional
  // and default to r. The "spectral file.rfl" and "xyz x y z" forms are ignored with a warning.
  bool colour(const std::string& kw, const std::vector<Token>& args, std::optional<glm::dvec3>* out) {
    if (args.empty()) return fail("'" + kw + "' needs a colour (r [g b])");
    if (args[0].text == "spectral" || args[0].text == "xyz") {
      warn("'" + kw + " " + args[0].text + "' colours are not supported; the statement is ignored");
      return true;
    }
    if (args.size() != 1 && args.size() != 3) {
      return fail("'" + kw + "' takes 1 or 3 numbers (r [g b]), got " + count(args.size()));
    }
    glm::dvec3 c;
    for (size_t i = 0; i < 3; ++i) {
      if (!number(kw, args[std::min(i, args.size() - 1)].text, &c[int(i)])) return false;
    }
    *out = c;
    return true;
  }

  bool scalar(const std::string& kw, const std::vector<Token>& args, std::optional<double>* out) {
    if (args.size() != 1) return fail("'" + kw + "' takes one number, got " + count(args.size()));
    double v;
    if (!number(kw, args[0].text, &v)) return false;
    if (out) *out = v;
    return true;
  }

  // Options, then the file name: the rest of the line, so that names with spaces work (MTL
  // spec, "Texture map statements": "map_Kd -options args filename").
  bool map(const std::string& line, const std::vector<Token>& tok, MtlMap* out) {
    const std::string& kw = tok[0].text;
    MtlMap m;
    m.present = true;
    m.statement = kw;
    m.line = line_;
    size_t i = 1;
    auto numbers = [&](const std::string& opt, size_t min, size_t max, double* v) {
      size_t n = 0;
      while (n < max && i < tok.size() && is_decimal_number(tok[i].text)) {
        if (!number(kw + " " + opt, tok[i++].text, &v[n++])) return false;
      }
      if (n < min) {
        return fail("'" + kw + "' option " + opt + " needs " +
                    (min == max ? std::to_string(min) : std::to_string(min) + " to " + std::to_string(max)) +
                    (max == 1 ? " number" : " numbers") +
                    (i < tok.size() ? ", got \"" + tok[i].text + "\"" : ", got none"));
      }
      return true;
    };
    while (i < tok.size() && tok[i].text.size() > 1 && tok[i].text[0] == '-' && !is_decimal_number(tok[i].text)) {
      const std::string opt = tok[i++].text;
      if (opt == "-blendu" || opt == "-blendv" || opt == "-cc" || opt == "-clamp") {
        if (i >= tok.size() || (tok[i].text != "on" && tok[i].text != "off")) {
          return fail("'" + kw + "' option " + opt + " takes on or off" +
                      (i < tok.size() ? ", got \"" + tok[i].text + "\"" : ""));
        }
        const bool on = tok[i++].text == "on";
        if (opt == "-clamp") {
          m.clamp = on;
        } else if ((opt == "-cc") == on) {  // not the default (blending on, colour correction off)
          m.ignored.push_back(opt + (on ? " on" : " off"));
        }
      } else if (opt == "-bm") {
        double v;
        if (!numbers(opt, 1, 1, &v)) return false;
        m.bm = v;
      } else if (opt == "-boost" || opt == "-texres") {
        double v;
        if (!numbers(opt, 1, 1, &v)) return false;
        m.ignored.push_back(opt);
      } else if (opt == "-mm") {
        double v[2] = {0.0, 1.0};
        if (!numbers(opt, 1, 2, v)) return false;
        m.mm_base = v[0];
        m.mm_gain = v[1];
      } else if (opt == "-o" || opt == "-s" || opt == "-t") {
        // Defaults of the components not given: -o 0 0 0, -s 1 1 1, -t 0 0 0 (MTL spec).
        const double def = opt == "-s" ? 1.0 : 0.0;
        double v[3] = {def, def, def};
        if (!numbers(opt, 1, 3, v)) return false;
        if (opt == "-o") {
          m.offset = glm::dvec2(v[0], v[1]);
        } else if (opt == "-s") {
          if (v[0] == 0.0 || v[1] == 0.0) return fail("'" + kw + "' option -s must not scale by 0");
          m.scale = glm::dvec2(v[0], v[1]);
        } else if (v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0) {
          m.ignored.push_back(opt);
        }
      } else if (opt == "-imfchan") {
        static const std::string kChannels = "rgbmlz";
        if (i >= tok.size() || tok[i].text.size() != 1 || kChannels.find(tok[i].text[0]) == std::string::npos) {
          return fail("'" + kw + "' option -imfchan takes one of r, g, b, m, l, z" +
                      (i < tok.size() ? ", got \"" + tok[i].text + "\"" : ""));
        }
        m.imfchan = tok[i++].text[0];
      } else if (opt == "-type") {
        if (i >= tok.size()) return fail("'" + kw + "' option -type needs a value");
        ++i;
        m.ignored.push_back(opt);
      } else {
        return fail("'" + kw + "' has an unknown option \"" + opt + "\"");
      }
    }
    if (i >= tok.size()) return fail("'" + kw + "' names no file");
    m.file = line.substr(tok[i].begin);
    while (!m.file.empty() && is_blank(m.file.back())) m.file.pop_back();
    if (out) *out = std::move(m);
    return true;
  }

  bool statement(const std::string& line, std::vector<Token> tok) {
    const std::string kw = tok[0].text;
    MtlMaterial* m = current_;
    // Texture maps first: their file name may hold anything, '#' included.
    static const std::set<std::string> kMaps = {"map_Ka", "map_Kd",  "map_Ks",   "map_Ns", "map_d",
                                                "map_Ke", "map_Pr",  "map_Pm",   "map_Ps", "bump",
                                                "map_bump", "map_Bump", "norm",  "disp",   "map_disp",
                                                "decal",  "refl"};
    if (kMaps.count(kw)) {
      if (!m) return fail("'" + kw + "' comes before any newmtl");
      MtlMap* target = nullptr;
      if (kw == "map_Kd") target = &m->map_kd;
      else if (kw == "map_Ks") target = &m->map_ks;
      else if (kw == "map_Ns") target = &m->map_ns;
      else if (kw == "map_d") target = &m->map_d;
      else if (kw == "map_Ke") target = &m->map_ke;
      else if (kw == "map_Pr") target = &m->map_pr;
      else if (kw == "map_Pm") target = &m->map_pm;
      else if (kw == "bump" || kw == "map_bump" || kw == "map_Bump") target = &m->bump;
      else if (kw == "norm") target = &m->norm;
      else if (kw != "map_Ka") m->ignore(kw);  // map_Ka: the ambient term, ignored silently
      return map(line, tok, target);
    }
    // Elsewhere '#' starts a comment.
    for (size_t i = 1; i < tok.size(); ++i) {
      if (tok[i].text[0] == '#') {
        tok.resize(i);
        break;
      }
    }
    const std::vector<Token> args(tok.begin() + 1, tok.end());

    if (kw == "newmtl") {
      if (args.empty()) return fail("'newmtl' names no material");
      const std::string& name = args[0].text;
      if (args.size() > 1) {
        // OBJ's "usemtl" names a material with one word (tinyobjloader reads the first).
        warn("the material name \"" + line.substr(args[0].begin) + "\" has spaces; it is read as \"" + name +
             "\", as usemtl reads it");
      }
      auto seen = defined_->find(name);
      if (seen != defined_->end()) {
        warn("material '" + name + "' is defined again; the first definition (" + seen->second +
             ") is used");
        discard_ = MtlMaterial();
        current_ = &discard_;
        return true;
      }
      (*defined_)[name] = "\"" + library_ + "\", line " + std::to_string(line_);
      materials_->push_back(MtlMaterial());
      current_ = &materials_->back();
      current_->name = name;
      current_->library = library_;
      current_->library_dir = library_dir_;
      return true;
    }

    static const std::set<std::string> kKnown = {
        "Ka", "Kd", "Ks", "Ke", "Tf", "Kt", "Ns", "Ni", "d", "Tr", "illum", "sharpness", "Pr", "Pm",
        "Ps", "Pc", "Pcr", "aniso", "anisor", "map_aat"};
    if (!kKnown.count(kw)) {
      if (unknown_.insert(kw).second) warn("unknown statement '" + kw + "' (ignored)");
      return true;
    }
    if (!m) return fail("'" + kw + "' comes before any newmtl");

    if (kw == "Kd") return colour(kw, args, &m->kd);
    if (kw == "Ks") return colour(kw, args, &m->ks);
    if (kw == "Ke") return colour(kw, args, &m->ke);
    if (kw == "Tf" || kw == "Kt") return colour(kw, args, &m->tf);
    if (kw == "Ka") {  // the ambient term: checked, then ignored silently (docs/obj-mtl.md)
      std::optional<glm::dvec3> unused;
      return colour(kw, args, &unused);
    }
    if (kw == "Ns") return scalar(kw, args, &m->ns);
    if (kw == "Ni") return scalar(kw, args, &m->ni);
    if (kw == "Tr") return scalar(kw, args, &m->tr);
    if (kw == "Pr") return scalar(kw, args, &m->pr);
    if (kw == "Pm") return scalar(kw, args, &m->pm);
    if (kw == "sharpness") return scalar(kw, args, nullptr);  // reflection maps only: ignored
    if (kw == "Ps" || kw == "Pc" || kw == "Pcr" || kw == "aniso" || kw == "anisor") {
      m->ignore(kw);
      return scalar(kw, args, nullptr);
    }
    if (kw == "d") {  // "d factor" or "d -halo factor"
      std::vector<Token> rest = args;
      if (!rest.empty() && rest[0].text == "-halo") {
        m->d_halo = true;
        rest.erase(rest.begin());
      }
      return scalar(kw, rest, &m->d);
    }
    if (kw == "illum") {
      // MTL spec, "illum illum_#": an illumination model from 0 to 10.
      const bool digits = args.size() == 1 && args[0].text.size() <= 2 &&
                          std::all_of(args[0].text.begin(), args[0].text.end(),
                                      [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
      if (!digits || std::atoi(args[0].text.c_str()) > 10) {
        return fail("'illum' takes an illumination model, an integer from 0 to 10; got " +
                    (args.size() == 1 ? "\"" + args[0].text + "\"" : count(args.size())));
      }
      m->illum = std::atoi(args[0].text.c_str());
      return true;
    }
    if (kw == "map_aat") {  // texture anti-aliasing: archwave filters every texture
      if (args.size() != 1 || (args[0].text != "on" && args[0].text != "off")) {
        return fail("'map_aat' takes on or off");
      }
      return true;
    }
    return true;
  }

  std::string library_, library_dir_;
  std::vector<MtlMaterial>* materials_;
  std::map<std::string, std::string>* defined_;
  std::vector<std::string>* warnings_;
  std::string* error_ = nullptr;
  size_t line_ = 0;
  MtlMaterial* current_ = nullptr;
  MtlMaterial discard_;  // a second definition of a name, parsed (checked) and dropped
  std::set<std::string> unknown_;
};

// The file names of the OBJ's mtllib statements, in order, each once. tinyobjloader reads
// "mtllib a.mtl b.mtl" only up to the first file it can load (it takes the names for
// alternatives), while an OBJ's mtllib loads every file it names; so the names are collected
// here, split as tinyobjloader splits them (spaces, "\ " for a space inside a name), and every
// library is read before tinyobjloader parses the OBJ.
std::vector<std::string> mtllib_names(const std::string& obj_text) {
  std::vector<std::string> names;
  std::istringstream lines(obj_text);
  for (std::string line; std::getline(lines, line);) {
    size_t i = 0;
    while (i < line.size() && is_blank(line[i])) ++i;
    if (line.compare(i, 6, "mtllib") != 0 || i + 6 >= line.size() || !is_blank(line[i + 6])) continue;
    std::string name;
    bool escaped = false;
    auto flush = [&]() {
      if (!name.empty() && std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
      name.clear();
    };
    for (size_t k = i + 7; k < line.size(); ++k) {
      const char c = line[k];
      if (escaped) {
        name += c;
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (is_blank(c)) {
        flush();
      } else if (c == '#' && name.empty()) {
        break;
      } else {
        name += c;
      }
    }
    flush();
  }
  return names;
}

// tinyobjloader's hook for mtllib statements. The libraries are parsed already (above); at the
// first mtllib statement every material of them is handed over, one name-only material_t per
// MtlMaterial in the same order, so that a face's material id indexes ObjImport::materials.
class PreparsedMaterials : public tinyobj::MaterialReader {
 public:
  explicit PreparsedMaterials(const std::vector<MtlMaterial>* materials) : materials_(materials) {}
  bool operator()(const std::string&, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* map, std::string*, std::string*) override {
    if (handed_over_) return true;
    handed_over_ = true;
    for (const MtlMaterial& m : *materials_) {
      tinyobj::material_t t{};
      t.name = m.name;
      (*map)[m.name] = static_cast<int>(materials->size());
      materials->push_back(t);
    }
    return true;
  }

 private:
  const std::vector<MtlMaterial>* materials_;
  bool handed_over_ = false;
};

// ---- MTL to the Architectural material ---------------------------------------------------------

class MtlConverter {
 public:
  MtlConverter(ObjImport* out, std::vector<std::string>* warnings) : out_(out), warnings_(warnings) {}

  bool convert(const MtlMaterial& mm, std::string* error) {
    error_ = error;
    MaterialDesc m;
    TextureBindings b;
    if (!convert(mm, &m, &b)) return false;
    out_->material_names.push_back(mm.name);
    out_->materials.push_back(std::move(m));
    out_->bindings.push_back(std::move(b));
    return true;
  }

 private:
  std::string label(const MtlMaterial& mm) const { return "material '" + mm.name + "' (" + mm.library + ")"; }

  void warn(const MtlMaterial& mm, const std::string& message) {
    const std::string full = label(mm) + ": " + message;
    if (warned_.insert(full).second) warnings_->push_back(full);
  }

  bool fail(const std::string& message) {
    *error_ = message;
    return false;
  }

  glm::dvec3 clamp_colour(const MtlMaterial& mm, const char* what, const glm::dvec3& c, double hi) {
    const glm::dvec3 r = glm::clamp(c, glm::dvec3(0.0), glm::dvec3(hi));
    if (r != c) {
      warn(mm, std::string(what) + " " + fmt(c) + " is outside [0, " + (std::isinf(hi) ? "inf" : fmt(hi)) +
                   "], clamped");
    }
    return r;
  }

  double clamp_scalar(const MtlMaterial& mm, const char* what, double v, double lo, double hi) {
    if (v < lo || v > hi) {
      warn(mm, std::string(what) + " " + fmt(v) + " is outside [" + fmt(lo) + ", " + fmt(hi) + "], clamped");
      return std::min(std::max(v, lo), hi);
    }
    return v;
  }

  // The MTL spec multiplies a colour map by its statement's colour ("map_Kd ... is multiplied by
  // the Kd value"); a TextureRef's multiplier is one number. No colour: the map as it is. A
  // grey colour is exact; a coloured one is replaced by its Rec. 709 luminance, with a warning
  // (as the glTF importer does, docs/gltf.md). A black one with a map is taken as 1, with a
  // warning: a map multiplied by black is the constant black, never what a file with a map means.
  float colour_factor(const MtlMaterial& mm, const std::optional<glm::dvec3>& c, const char* what,
                      const char* map) {
    if (!c) return 1.0f;
    const glm::dvec3 v = *c;
    if (v == glm::dvec3(0.0)) {
      warn(mm, std::string(what) + " is black; " + map + " is used as it is");
      return 1.0f;
    }
    if (v.x == v.y && v.y == v.z) return float(v.x);
    const double lum = luminance(v);
    warn(mm, std::string(what) + " " + fmt(v) + " multiplies " + map + "; a texture's multiplier is one number, " +
                 "its luminance " + fmt(lum) + " is used");
    return float(lum);
  }

  // The same for a scalar (d with map_d, Pr with map_Pr): absent or 0 with a map: 1.
  float scalar_factor(const MtlMaterial& mm, const std::optional<double>& v, const char* what, const char* map) {
    if (!v) return 1.0f;
    if (*v == 0.0) {
      warn(mm, std::string(what) + " is 0; " + map + " is used as it is");
      return 1.0f;
    }
    return float(*v);
  }

  // The channel a scalar input reads. -imfchan (MTL spec, "-imfchan r | g | b | m | l | z"): r,
  // g, b; m (matte) the alpha; l the luminance; z (depth) has no meaning for an image here.
  // Without it: the luminance, or with alpha_if_any the alpha when the image has one.
  int scalar_channel(const MtlMaterial& mm, const MtlMap& map, const TextureDesc& t, bool alpha_if_any) {
    switch (map.imfchan) {
      case 'r': return 0;
      case 'g': return 1;
      case 'b': return 2;
      case 'm': return 3;
      case 'l': return -1;
      case 'z':
        warn(mm, map.statement + ": -imfchan z (depth) is not supported; the default channel is read");
        break;
      default:
        break;
    }
    return alpha_if_any && (t.channels == 2 || t.channels == 4) ? 3 : -1;
  }

  // A tangent-space normal map stores (n + 1) / 2 with n mostly near +z: its mean colour is
  // close to (0.5, 0.5, 1). A height map is grey (R = G = B) or one channel; it does not.
  static bool looks_like_normal_map(const TextureDesc& t) {
    if (t.channels < 3 || t.texels.empty()) return false;
    double r = 0.0, g = 0.0, bl = 0.0;
    const size_t n = t.texels.size() / 4;
    for (size_t i = 0; i < n; ++i) {
      r += t.texels[4 * i];
      g += t.texels[4 * i + 1];
      bl += t.texels[4 * i + 2];
    }
    r /= double(n);
    g /= double(n);
    bl /= double(n);
    return bl >= 0.8 && std::abs(r - 0.5) <= 0.15 && std::abs(g - 0.5) <= 0.15;
  }

  // Takes back the texture texture() has just added for `file` (no binding refers to it).
  void forget_last_texture(const std::string& file) {
    const uint32_t id = static_cast<uint32_t>(out_->textures.size() - 1);
    for (auto it = texture_ids_.begin(); it != texture_ids_.end();) {
      it = it->second == id ? texture_ids_.erase(it) : std::next(it);
    }
    for (auto it = decoded_.begin(); it != decoded_.end();) {
      it = it->second == id ? decoded_.erase(it) : std::next(it);
    }
    --variants_[file];
    out_->textures.pop_back();
  }

  // The TextureDesc of a map in a colour space: one per (file, colour space, -s, -o, -clamp),
  // the image decoded once per (file, colour space).
  bool texture(const MtlMaterial& mm, const MtlMap& map, bool srgb, uint32_t* id) {
    const std::string resolved = (fs::path(mm.library_dir) / map.file).lexically_normal().string();
    TextureDesc t;
    t.type = TextureDesc::Type::Image;
    t.colorspace = srgb ? TextureDesc::ColorSpace::Srgb : TextureDesc::ColorSpace::Linear;
    // -clamp on (MTL spec: "one copy of the texture is mapped onto the surface ... outside of
    // the original texture, the underlying material is unchanged"): archwave has no "no texture
    // here"; Clamp repeats the edge texels outside [0, 1] (docs/obj-mtl.md).
    t.wrap = map.clamp ? TextureDesc::Wrap::Clamp : TextureDesc::Wrap::Repeat;
    // -s and -o as uv' = s * uv + o: TextureDesc's transform with rotation 0.
    t.scale = glm::vec2(map.scale);
    t.offset = glm::vec2(map.offset);
    const auto key = std::make_tuple(resolved, srgb, t.scale.x, t.scale.y, t.offset.x, t.offset.y, int(t.wrap));
    auto it = texture_ids_.find(key);
    if (it != texture_ids_.end()) {
      *id = it->second;
      return true;
    }
    const int variant = variants_[map.file]++;
    t.name = map.file + (variant ? " (" + std::to_string(variant + 1) + ")" : "");
    t.source = resolved;
    auto dec = decoded_.find({resolved, srgb});
    if (dec != decoded_.end()) {
      copy_decoded_image(out_->textures[dec->second], &t);
    } else {
      std::string err;
      if (!load_texture_file(resolved, &t, &err)) {
        return fail(label(mm) + ": line " + std::to_string(map.line) + ": " + map.statement + " \"" + map.file +
                    "\": " + err);
      }
      decoded_[{resolved, srgb}] = out_->textures.size();
    }
    *id = static_cast<uint32_t>(out_->textures.size());
    out_->textures.push_back(std::move(t));
    texture_ids_[key] = *id;
    return true;
  }

  // Binds `key` to `map`: value = offset + multiplier * texel, with the map's -mm base gain
  // (MTL spec: "-mm base_value gain_value" adds base to the texel values and scales them by
  // gain) folded in: offset + multiplier * (base + gain * texel). The channel: RGB for colours,
  // as scalar_channel decides for scalars (scalar = true).
  bool bind(const MtlMaterial& mm, const MtlMap& map, bool srgb, const std::string& key, bool scalar,
            float multiplier, float offset, TextureBindings* b, bool alpha_if_any = false) {
    uint32_t id = 0;
    if (!texture(mm, map, srgb, &id)) return false;
    TextureRef r;
    r.texture = id;
    if (scalar) {
      r.channel = scalar_channel(mm, map, out_->textures[id], alpha_if_any);
    } else if (map.imfchan) {
      warn(mm, map.statement + ": -imfchan applies to scalar textures only (ignored)");
    }
    r.multiplier = float(multiplier * map.mm_gain);
    r.offset = float(offset + multiplier * map.mm_base);
    (*b)[key] = r;
    for (const std::string& opt : map.ignored) warn(mm, map.statement + ": option " + opt + " is ignored");
    if (map.bm && key != "bump.input") warn(mm, map.statement + ": -bm applies to bump maps only (ignored)");
    return true;
  }

  bool convert(const MtlMaterial& mm, MaterialDesc* out, TextureBindings* b) {
    MaterialDesc m;
    m.diffuse.weight = 1.0f;
    m.diffuse.roughness = 0.0f;  // Lambert: the MTL spec's diffuse term is (N . L)

    // Illumination model (MTL spec, "illum illum_#"). The spec gives no default; without one
    // the material is read as illum 2 (diffuse and highlights), what exporters mean by Kd/Ks.
    int illum = mm.illum < 0 ? 2 : mm.illum;
    if (illum == 0) warn(mm, "illum 0 (a constant colour, no lighting) is approximated by illum 1 (diffuse)");
    if (illum == 10) {
      warn(mm, "illum 10 (casts shadows onto invisible surfaces) is not supported; read as illum 2");
      illum = 2;
    }
    const bool highlights = illum >= 2;                // 0 and 1 have no specular term
    const bool mirror = illum >= 3 && illum <= 9;      // a ray-traced (or mapped) mirror reflection
    const bool glass = illum == 4 || illum == 6 || illum == 7 || illum == 9;  // transparency

    // ---- diffuse: Kd, map_Kd (sRGB) ----
    std::optional<glm::dvec3> kd;
    if (mm.kd) kd = clamp_colour(mm, "Kd", *mm.kd, 1.0);
    m.diffuse.color = glm::vec3(kd ? *kd : glm::dvec3(0.5));  // no Kd: MaterialDesc's default grey
    if (mm.map_kd.present &&
        !bind(mm, mm.map_kd, true, "diffuse.color", false, colour_factor(mm, kd, "Kd", "map_Kd"), 0.0f, b)) {
      return false;
    }

    // ---- the PBR extension: Pm, Pr, map_Pr ----
    const bool pbr = mm.pr || mm.pm || mm.map_pr.present;
    const double pm = mm.pm ? clamp_scalar(mm, "Pm", *mm.pm, 0.0, 1.0) : 0.0;
    // archwave's metal switches the whole material (as for glTF's metallicFactor, docs/gltf.md).
    m.metal = pm >= 0.5;
    if (pm > 0.0 && pm < 1.0) {
      warn(mm, "Pm " + fmt(pm) + " is taken as " + (m.metal ? "metal" : "dielectric") +
                   " (archwave's metal is on or off)");
    }
    if (mm.map_pm.present) {
      warn(mm, "map_Pm cannot switch metal per texel (ignored); Pm makes the material " +
                   std::string(m.metal ? "a metal" : "a dielectric"));
    }

    // ---- reflection weight and colour: Ks, map_Ks ----
    if (m.metal) {
      // The diffuse colour tints a metal's reflection (metal), so the lobe is white, at full
      // weight, with a Fresnel factor of 1 at every angle (facing = perpendicular = 1), as the
      // glTF importer's metals. Ks and map_Ks describe a dielectric's highlight: not used.
      m.reflection.weight = 1.0f;
      m.reflection.color = glm::vec3(1.0f);
      m.reflection.fresnel.use_ior = false;
      m.reflection.fresnel.facing = 1.0f;
      m.reflection.fresnel.perpendicular = 1.0f;
      if (mm.map_ks.present) warn(mm, "map_Ks is ignored for a metal (Pm): the diffuse colour tints its reflection");
    } else if (!highlights && !pbr) {
      m.reflection.weight = 0.0f;
      if ((mm.ks && *mm.ks != glm::dvec3(0.0)) || mm.map_ks.present) {
        warn(mm, "illum " + std::to_string(illum) + " has no specular term; Ks and map_Ks are ignored");
      }
    } else {
      // weight = max(Ks), colour = Ks / max(Ks): the colour keeps its hue at full value and the
      // weight says how much. Without Ks: none, except for a PBR-extension material, whose
      // specular layer is always there (as glTF's), and with map_Ks alone.
      std::optional<glm::dvec3> ks;
      if (mm.ks) ks = clamp_colour(mm, "Ks", *mm.ks, 1.0);
      glm::dvec3 k = ks ? *ks : glm::dvec3(pbr ? 1.0 : 0.0);
      double w = std::max(k.x, std::max(k.y, k.z));
      if (mm.map_ks.present && w == 0.0) {
        if (ks) warn(mm, "Ks is black; map_Ks is used as it is");
        k = glm::dvec3(1.0);
        w = 1.0;
      }
      m.reflection.weight = float(w);
      const glm::dvec3 colour = w > 0.0 ? k / w : glm::dvec3(1.0);
      m.reflection.color = glm::vec3(colour);
      if (mm.map_ks.present &&
          !bind(mm, mm.map_ks, true, "reflection.color", false, colour_factor(mm, colour, "Ks's colour", "map_Ks"), 0.0f,
                b)) {
        return false;
      }
    }

    // ---- glossiness: Pr / map_Pr, the illumination model, or Ns ----
    if (mm.pr || mm.map_pr.present) {
      // The extension's roughness is glTF's (alpha = r^2): g = 1 - r is exact, with archwave's
      // alpha = (1 - g)^2 (docs/material.md §3.3, docs/gltf.md), on GGX. map_Pr: 1 - Pr * texel.
      const double pr = mm.pr ? clamp_scalar(mm, "Pr", *mm.pr, 0.0, 1.0) : 0.0;
      m.reflection.brdf = Brdf::Ggx;
      m.reflection.glossiness = float(1.0 - pr);
      if (mm.map_pr.present) {
        const float f = scalar_factor(mm, mm.pr ? std::optional<double>(pr) : std::nullopt, "Pr", "map_Pr");
        if (!bind(mm, mm.map_pr, false, "reflection.glossiness", true, -f, 1.0f, b)) return false;
      }
    } else if (mirror) {
      // Models 3 to 9 add a mirror reflection (ray traced, or from a reflection map in 8 and 9,
      // which a path tracer traces instead). One lobe cannot be both the Ns highlight and the
      // mirror: the mirror is what these models add, so the lobe is one (glossiness 1).
      m.reflection.brdf = Brdf::Ggx;
      m.reflection.glossiness = 1.0f;
    } else {
      // Ns: the exponent of the spec's Blinn-Phong highlight, (N . H)^Ns (MTL spec, "illum"
      // models 2 and up). Walter et al. 2007, "Microfacet Models for Refraction through Rough
      // Surfaces", Sec. 5.2: a Phong exponent n corresponds to alpha = sqrt(2 / (n + 2)); with
      // archwave's alpha = (1 - g)^2, g = 1 - (2 / (n + 2))^(1/4). archwave's
      // Ashikhmin-Shirley lobe uses the same relation backwards (exponent 2 / alpha^2 - 2,
      // docs/material.md §3.3), so on that lobe the highlight's exponent is Ns exactly. No Ns:
      // 0, the broadest lobe (the spec gives no default).
      const double n = mm.ns ? clamp_scalar(mm, "Ns", *mm.ns, 0.0, std::numeric_limits<double>::max()) : 0.0;
      m.reflection.brdf = Brdf::AshikhminShirley;
      m.reflection.glossiness = float(1.0 - std::pow(2.0 / (n + 2.0), 0.25));
    }
    if (mm.map_ns.present) {
      warn(mm, "map_Ns is not supported (ignored): a map of Phong exponents is not linear in glossiness");
    }

    // ---- index of refraction, and the reflection's Fresnel: Ni ----
    // Ni (MTL spec: "optical_density", 0.001 to 10, 1.0 = no bending). No Ni: 1.5 (glass; glTF's
    // default). Below 1: 1.5, with a warning (as for glTF's ior). The reflection's Fresnel is the
    // dielectric's from this IOR (the material's default, locked to refraction.ior), so Ks scales
    // a physically shaped reflection. Ni 1 (exporters write it as "none") would make that Fresnel
    // 0 and hide Ks: the reflection then takes its own IOR 1.5, refraction keeps Ni.
    double ior = 1.5;
    bool own_reflection_ior = false;
    if (mm.ni) {
      if (*mm.ni < 1.0) {
        warn(mm, "Ni " + fmt(*mm.ni) + " is below 1; 1.5 is used");
      } else {
        ior = *mm.ni;
        own_reflection_ior = ior < 1.001;  // docs/material.md §3.5: |eta - 1| < 1e-3 passes through
      }
    }
    m.refraction.ior = float(ior);
    if (!m.metal) {
      m.reflection.fresnel.use_ior = true;
      m.reflection.fresnel.lock_to_refraction_ior = !own_reflection_ior;
      if (own_reflection_ior) {
        m.reflection.fresnel.ior = 1.5f;
        if (m.reflection.weight > 0.0f) {
          warn(mm, "Ni " + fmt(ior) + " gives no Fresnel reflection; the reflection uses IOR 1.5");
        }
      }
    }

    // ---- transparency: d, Tr, map_d, Tf ----
    // d = 1 is opaque (MTL spec, "d factor"). Tr is not in the spec; exporters write it as
    // 1 - d (tinyobjloader reads it so); d wins when both are given.
    std::optional<double> d;
    if (mm.d) d = clamp_scalar(mm, "d", *mm.d, 0.0, 1.0);
    if (mm.d && mm.tr) {
      warn(mm, "both d and Tr are given; d is used");
    } else if (mm.tr) {
      d = 1.0 - clamp_scalar(mm, "Tr", *mm.tr, 0.0, 1.0);
    }
    if (mm.d_halo) warn(mm, "d -halo (dissolve that depends on the view) is approximated by a constant d");
    const double dv = d ? *d : 1.0;
    const bool transparent = dv < 1.0 || mm.map_d.present;
    if (glass && transparent && m.metal) {
      warn(mm, "a metal (Pm) transmits nothing; d, Tr and map_d are ignored");
    } else if (glass && transparent) {
      // The glass models (4, 6, 7, 9): what d lets through is refracted, tinted by the
      // transmission filter Tf, through the interface of IOR Ni, smooth. The split gives
      // refraction its weight of what reflection leaves (docs/material.md §2).
      m.refraction.weight = float(1.0 - dv);
      m.refraction.color = glm::vec3(mm.tf ? clamp_colour(mm, "Tf", *mm.tf, 1.0) : glm::dvec3(1.0));
      m.refraction.glossiness = 1.0f;
      if (mm.map_d.present) {
        // refraction.weight = 1 - d * texel; the texel: alpha when the image has one.
        const float f = scalar_factor(mm, d, "d", "map_d");
        if (!bind(mm, mm.map_d, false, "refraction.weight", true, -f, 1.0f, b, true)) return false;
      }
    } else if (mm.map_d.present) {
      // Other models: the dissolve map cuts the surface out where d * texel < 0.5 (archwave's
      // cutout threshold, docs/material.md §1). The texel: alpha when the image has one.
      m.cutout_opacity = float(dv);
      const float f = scalar_factor(mm, d, "d", "map_d");
      if (!bind(mm, mm.map_d, false, "cutout_opacity", true, f, 0.0f, b, true)) return false;
    } else if (dv < 1.0) {
      // A constant partial dissolve: archwave has cutouts, no blending. Below 0.5 the surface is
      // cut out entirely; from 0.5 up it is opaque.
      m.cutout_opacity = float(dv);
      warn(mm, "d " + fmt(dv) + " without a glass illumination model (4, 6, 7, 9): archwave has no partial " +
                   (dv < 0.5 ? "dissolve; below 0.5 the surface is cut out entirely"
                             : "dissolve; from 0.5 up the surface is opaque"));
    }

    // ---- emission: Ke, map_Ke (sRGB) ----
    std::optional<glm::dvec3> ke;
    if (mm.ke) ke = clamp_colour(mm, "Ke", *mm.ke, std::numeric_limits<double>::infinity());
    m.incandescent.color = glm::vec3(ke ? *ke : glm::dvec3(0.0));
    m.incandescent.scale = 1.0f;
    if (mm.map_ke.present &&
        !bind(mm, mm.map_ke, true, "incandescent.color", false, colour_factor(mm, ke, "Ke", "map_Ke"), 0.0f, b)) {
      return false;
    }

    // ---- bump (linear; luminance unless -imfchan, the spec's default "l" for bump) ----
    if (mm.bump.present) {
      const size_t textures_before = out_->textures.size();
      if (!bind(mm, mm.bump, false, "bump.input", true, 1.0f, 0.0f, b)) return false;
      const TextureDesc& t = out_->textures[(*b)["bump.input"].texture];
      if (looks_like_normal_map(t)) {
        // Exporters without a normal-map statement (Blender's among them) write tangent-space
        // normal maps as map_Bump. Read as heights, such a map would tilt the surface at
        // random; it is recognised by its colour and left out.
        warn(mm, mm.bump.statement + " \"" + mm.bump.file +
                     "\" looks like a tangent-space normal map (mean colour near (0.5, 0.5, 1)), not a height map; " +
                     "normal maps are not supported yet (ignored)");
        b->erase("bump.input");
        if (out_->textures.size() > textures_before) forget_last_texture(mm.bump.file);
      } else {
        m.bump.input = t.name;
        m.bump.scale = float((mm.bump.bm ? *mm.bump.bm : 1.0) * kMtlBumpUnit);
      }
    }
    if (mm.norm.present) warn(mm, "norm (a normal map) is not supported yet (ignored)");

    for (const std::string& s : mm.ignored) warn(mm, s + " is not supported (ignored)");
    *out = m;
    return true;
  }

  ObjImport* out_;
  std::vector<std::string>* warnings_;
  std::string* error_ = nullptr;
  std::set<std::string> warned_;
  std::map<std::tuple<std::string, bool, float, float, float, float, int>, uint32_t> texture_ids_;
  std::map<std::pair<std::string, bool>, size_t> decoded_;
  std::map<std::string, int> variants_;
};

// Reads one library (relative to the OBJ's folder) into materials: false with *error on an
// unreadable or malformed file; a missing file is a warning.
bool read_library(const std::string& name, const fs::path& obj_dir, std::map<std::string, std::string>* defined,
                  std::vector<MtlMaterial>* materials, std::vector<std::string>* warnings, std::string* error) {
  const fs::path path = (obj_dir / name).lexically_normal();
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) {
    warnings->push_back("material library \"" + name +
                        "\" does not exist; the faces that use its materials have no material");
    return true;
  }
  if (fs::is_directory(status)) {
    *error = "material library \"" + name + "\" is a directory, not a file";
    return false;
  }
  std::ifstream file(path, std::ios::binary);
  if (!file.is_open()) {
    *error = "material library \"" + name + "\": cannot open: " + std::strerror(errno);
    return false;
  }
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad()) {
    *error = "material library \"" + name + "\": read error";
    return false;
  }
  MtlParser parser(name, path.parent_path().string(), materials, defined, warnings);
  return parser.parse(text.str(), error);
}

}  // namespace

bool load_obj_with_materials(const std::string& resolved_path, ObjImport* out, std::string* error,
                             std::vector<std::string>* warnings) {
  std::vector<std::string> local_warnings;
  if (!warnings) warnings = &local_warnings;
  *out = ObjImport();

  // 1. The OBJ's text, checked as load_obj checks it.
  std::string text;
  if (!read_obj_text(resolved_path, &text, error)) return false;

  // 2. Its material libraries. An error here is reported after the OBJ's own checks, so that a
  // broken OBJ reads the same as with load_obj.
  std::vector<MtlMaterial> mtl;
  std::vector<std::string> mtl_warnings;
  std::string mtl_error;
  {
    const fs::path obj_dir = fs::path(resolved_path).parent_path();
    std::map<std::string, std::string> defined;
    for (const std::string& name : mtllib_names(text)) {
      if (!read_library(name, obj_dir, &defined, &mtl, &mtl_warnings, &mtl_error)) break;
    }
  }

  // 3. The OBJ, its faces' materials resolved against those libraries.
  ObjData d;
  PreparsedMaterials reader(&mtl);
  std::vector<std::string> obj_warnings;
  if (!parse_obj_text(text, &reader, &d, error, &obj_warnings)) return false;
  if (!mtl_error.empty()) {
    *error = mtl_error;
    return false;
  }
  std::set<std::string> seen;
  for (const std::string& w : mtl_warnings) {
    if (seen.insert(w).second) warnings->push_back(w);
  }
  for (const std::string& w : obj_warnings) {  // "material [ 'x' ] not found" comes once per usemtl
    if (seen.insert(w).second) warnings->push_back(w);
  }

  // 4. The materials and their textures.
  ObjImport result;
  MtlConverter converter(&result, warnings);
  for (const MtlMaterial& m : mtl) {
    if (!converter.convert(m, error)) return false;
  }

  // 5. One primitive per material used, in order of first use.
  const int material_count = static_cast<int>(mtl.size());
  std::map<int, size_t> group_of;
  std::vector<std::vector<ObjTriangle>> groups;
  std::vector<int> group_material;
  for (const ObjTriangle& t : obj_triangles(d)) {
    const std::vector<int>& ids = d.shapes[t.shape].mesh.material_ids;
    int material = t.face < ids.size() ? ids[t.face] : -1;
    if (material < 0 || material >= material_count) material = -1;
    auto it = group_of.find(material);
    if (it == group_of.end()) {
      it = group_of.emplace(material, groups.size()).first;
      groups.emplace_back();
      group_material.push_back(material);
    }
    groups[it->second].push_back(t);
  }
  const size_t num_normals = d.attrib.normals.size() / 3;
  const size_t num_uvs = d.attrib.texcoords.size() / 2;
  for (size_t g = 0; g < groups.size(); ++g) {
    GltfPrimitive p;
    p.material = group_material[g];
    p.name = p.material >= 0 ? "material '" + mtl[size_t(p.material)].name + "'" : "faces without a material";
    // Normals and UVs per primitive: kept when every corner of its triangles has a valid one.
    // When the whole file has them, parse_obj_text has checked every index, so this is the
    // same choice as load_obj's; otherwise a part that has them keeps them.
    bool normals = true, uvs = true;
    for (const ObjTriangle& t : groups[g]) {
      const tinyobj::mesh_t& m = d.shapes[t.shape].mesh;
      for (size_t k = 0; k < 3; ++k) {
        const tinyobj::index_t& i = m.indices[t.offset + k];
        normals = normals && i.normal_index >= 0 && static_cast<size_t>(i.normal_index) < num_normals;
        uvs = uvs && i.texcoord_index >= 0 && static_cast<size_t>(i.texcoord_index) < num_uvs;
      }
    }
    deindex_obj(d, groups[g], normals, uvs, &p.mesh);
    if (!obj_normals_usable(p.mesh)) {
      // As load_obj: a normal that cannot be renormalised drops the normals (of this primitive).
      warnings->push_back("a vertex normal is zero or not finite; ignoring the normals of " + p.name);
      p.mesh.normals.clear();
    }
    result.primitives.push_back(std::move(p));
  }
  *out = std::move(result);
  return true;
}

}  // namespace scene_detail
}  // namespace aw
