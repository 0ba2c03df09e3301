// glTF 2.0 import through tinygltf (Debian's libtinygltf-dev, 2.7): geometry flattened into the
// glTF scene's space, materials converted to the Architectural material. The material mapping
// and what is approximated or ignored: docs/gltf.md. Section numbers "glTF 2.0 §x.y" refer to
// the Khronos glTF 2.0 specification (registry.khronos.org/glTF/specs/2.0/glTF-2.0.html).

// This header first: it includes nlohmann/json.hpp with default visibility. tinygltf includes
// it inside "#pragma GCC visibility push(hidden)", which, were it first, would hide the json
// types that the loader's own headers (LocatedJson) expose.
#include "host/scene/gltf_mesh.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <tuple>
#include <unordered_map>

#include <glm/gtc/quaternion.hpp>

// tinygltf parses JSON with nlohmann/json (its default, already a dependency). Images are not
// decoded by tinygltf: the callback below keeps the encoded bytes, and decode_texture_image
// decodes them later with the colour space their use needs (a base colour is sRGB, a roughness
// map linear), which tinygltf cannot know when it reads the image. External images are not read
// by tinygltf either (TINYGLTF_NO_EXTERNAL_IMAGE): tinygltf 2.7 does hand a URI image's bytes
// to the callback, but turns a missing image file into a warning and an empty image; reading
// it here with load_texture_file, only when a material uses it, gives a real error.
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
#include <tiny_gltf.h>

namespace aw {
namespace scene_detail {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;
// An accessor without a bufferView is all zeros (the accessor.bufferView property reference,
// glTF 2.0 §3.6.2.3); its count is then not
// bounded by any data in the file, so it is limited here before anything is allocated.
constexpr uint64_t kMaxZeroFilledCount = uint64_t(1) << 24;

std::string label(const char* kind, int index, const std::string& name) {
  return name.empty() ? std::string(kind) + " " + std::to_string(index)
                      : std::string(kind) + " '" + name + "'";
}

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// tinygltf's messages end in newlines, may hold several lines, and quote whole data URIs
// (megabytes of base64): one line, "; " between the lines, data URIs cut short.
std::string clean_message(const std::string& raw) {
  std::string text;
  for (size_t i = 0; i < raw.size();) {
    const size_t comma = raw.compare(i, 5, "data:") == 0 ? raw.find(";base64,", i) : std::string::npos;
    if (comma != std::string::npos && comma - i < 64) {
      size_t end = comma + 8;
      while (end < raw.size() && (std::isalnum(static_cast<unsigned char>(raw[end])) || raw[end] == '+' ||
                                  raw[end] == '/' || raw[end] == '=')) {
        ++end;
      }
      text.append(raw, i, comma + 8 - i);
      if (end > comma + 8) text += "...";
      i = end;
    } else {
      text += raw[i++];
    }
  }
  std::string out;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    size_t b = 0;
    while (b < line.size() && std::isspace(static_cast<unsigned char>(line[b]))) ++b;
    if (b == line.size()) continue;
    if (!out.empty()) out += "; ";
    out += line.substr(b);
  }
  return out;
}

uint32_t read_le32(const unsigned char* p) {
  return uint32_t(p[0]) | (uint32_t(p[1]) << 8) | (uint32_t(p[2]) << 16) | (uint32_t(p[3]) << 24);
}

// URIs in glTF are relative references, percent-encoded (glTF 2.0 §2.8 "URIs").
std::string percent_decode(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// File access for external buffers. tinygltf 2.7 looks for a buffer next to the glTF file and
// then in the current directory; only the first is right (glTF 2.0 §2.8: relative URIs resolve
// against the glTF file), so a file is accepted only under the glTF file's directory prefix.
struct FsContext {
  std::string prefix;  // the directory as tinygltf joins it, with a trailing '/'
};

bool fs_file_exists(const std::string& path, void* user) {
  const FsContext* ctx = static_cast<const FsContext*>(user);
  if (path.compare(0, ctx->prefix.size(), ctx->prefix) != 0) return false;
  std::error_code ec;
  return fs::is_regular_file(path, ec);
}

std::string fs_expand(const std::string& path, void*) { return path; }

bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& path, void*) {
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    if (err) *err += std::string("cannot open: ") + std::strerror(errno);
    return false;
  }
  out->assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  if (f.bad()) {
    if (err) *err += "read error";
    return false;
  }
  return true;
}

// tinygltf's image callback. Keeps the encoded bytes of data-URI images in Image::image
// (as_is); images stored in a bufferView are left alone, because tinygltf 2.7 passes
// &buffer.data[byteOffset] with byteLength without checking either against the buffer's size:
// those bytes are taken from the bufferView later, after a bounds check.
bool keep_encoded_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                        const unsigned char* bytes, int size, void*) {
  if (image->bufferView >= 0) return true;
  if (bytes && size > 0) image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

// A textureInfo (glTF 2.0 property reference, "textureInfo") with its KHR_texture_transform,
// read from tinygltf's struct or from an extension's JSON value.
struct TexInfo {
  int index = -1;
  int tex_coord = 0;
  bool transformed = false;
  glm::dvec2 offset{0.0}, scale{1.0};
  double rotation = 0.0;  // radians, as glTF gives it
  bool valid = true;      // false: malformed (message in `problem`)
  std::string problem;
};

const tinygltf::Value* member(const tinygltf::Value& v, const char* key) {
  if (!v.IsObject() || !v.Has(key)) return nullptr;
  return &v.Get(key);
}

bool number_of(const tinygltf::Value* v, double* out) {
  if (!v || !v->IsNumber()) return false;
  *out = v->GetNumberAsDouble();
  return true;
}

void read_transform(const tinygltf::Value& t, TexInfo* info) {
  info->transformed = true;
  auto vec2 = [&](const char* key, glm::dvec2* out) {
    const tinygltf::Value* v = member(t, key);
    if (!v) return;
    if (!v->IsArray() || v->ArrayLen() != 2 || !v->Get(0).IsNumber() || !v->Get(1).IsNumber()) {
      info->valid = false;
      info->problem = std::string("KHR_texture_transform.") + key + " is not an array of 2 numbers";
      return;
    }
    *out = glm::dvec2(v->Get(0).GetNumberAsDouble(), v->Get(1).GetNumberAsDouble());
  };
  vec2("offset", &info->offset);
  vec2("scale", &info->scale);
  if (const tinygltf::Value* r = member(t, "rotation")) {
    if (!number_of(r, &info->rotation)) {
      info->valid = false;
      info->problem = "KHR_texture_transform.rotation is not a number";
    }
  }
  if (const tinygltf::Value* tc = member(t, "texCoord")) {
    if (tc->IsInt()) info->tex_coord = tc->GetNumberAsInt();
  }
  if (!std::isfinite(info->offset.x) || !std::isfinite(info->offset.y) || !std::isfinite(info->scale.x) ||
      !std::isfinite(info->scale.y) || !std::isfinite(info->rotation)) {
    info->valid = false;
    info->problem = "KHR_texture_transform has a value that is not finite";
  }
}

TexInfo tex_info(const tinygltf::TextureInfo& t) {
  TexInfo info;
  info.index = t.index;
  info.tex_coord = t.texCoord;
  auto it = t.extensions.find("KHR_texture_transform");
  if (it != t.extensions.end()) read_transform(it->second, &info);
  return info;
}

TexInfo tex_info(const tinygltf::Value* v) {
  TexInfo info;
  if (!v) return info;
  if (!v->IsObject()) {
    info.valid = false;
    info.problem = "is not a JSON object";
    return info;
  }
  const tinygltf::Value* index = member(*v, "index");
  if (!index || !index->IsInt()) {
    info.valid = false;
    info.problem = "has no integer 'index'";
    return info;
  }
  info.index = index->GetNumberAsInt();
  if (info.index < 0) {
    info.valid = false;
    info.problem = "has a negative index";
    return info;
  }
  if (const tinygltf::Value* tc = member(*v, "texCoord")) {
    if (tc->IsInt()) info.tex_coord = tc->GetNumberAsInt();
  }
  if (const tinygltf::Value* ext = member(*v, "extensions")) {
    if (const tinygltf::Value* t = member(*ext, "KHR_texture_transform")) read_transform(*t, &info);
  }
  return info;
}

// One TextureDesc per distinct (glTF texture, colour space, UV transform).
struct TextureKey {
  int texture;
  bool srgb;
  double ox, oy, sx, sy, rot;
  bool operator<(const TextureKey& o) const {
    return std::tie(texture, srgb, ox, oy, sx, sy, rot) <
           std::tie(o.texture, o.srgb, o.ox, o.oy, o.sx, o.sy, o.rot);
  }
};

// Everything a material's conversion collects besides the MaterialDesc.
struct MaterialState {
  int index = 0;
  std::string name;  // "material 'Wood'" or "material 3", for messages
  TextureBindings bindings;
  std::set<std::string> warned;
};

class Importer {
 public:
  Importer(const std::string& path, GltfImport* out, std::string* error, std::vector<std::string>* warnings)
      : path_(path), out_(out), error_(error), warnings_(warnings) {
    file_name_ = fs::path(path).filename().string();
  }

  bool run() {
    std::vector<unsigned char> bytes;
    if (!read_file(&bytes)) return false;
    if (!parse(bytes)) return false;
    bytes.clear();
    bytes.shrink_to_fit();
    if (!check_extensions()) return false;
    if (!convert_materials()) return false;
    return import_scene();
  }

 private:
  // ---- reading and parsing ------------------------------------------------------------------

  bool fail(const std::string& message) {
    *error_ = message;
    return false;
  }

  void warn(const std::string& message) {
    if (warned_.insert(message).second) warnings_->push_back(message);
  }

  bool read_file(std::vector<unsigned char>* bytes) {
    std::error_code ec;
    const fs::file_status status = fs::status(path_, ec);
    if (!fs::exists(status)) return fail("no such file");
    if (fs::is_directory(status)) return fail("is a directory, not a file");
    std::ifstream f(path_, std::ios::binary);
    if (!f.is_open()) return fail(std::string("cannot open: ") + std::strerror(errno));
    bytes->assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
    if (f.bad()) return fail("read error");
    if (bytes->empty()) return fail("the file is empty");
    // tinygltf takes sizes as unsigned int; a .glb cannot be larger anyway (glTF 2.0 §4.4.2).
    if (bytes->size() >= (uint64_t(1) << 32)) return fail("the file is larger than 4 GiB");
    return true;
  }

  bool parse(const std::vector<unsigned char>& bytes) {
    fs::path dir = fs::path(path_).parent_path();
    std::string base = dir.empty() ? std::string(".") : dir.string();
    fs_ctx_.prefix = base.back() == '/' ? base : base + "/";
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(keep_encoded_image, nullptr);
    loader.SetFsCallbacks(tinygltf::FsCallbacks{fs_file_exists, fs_expand, fs_read, nullptr, &fs_ctx_});
    loader.SetStoreOriginalJSONForExtrasAndExtensions(false);

    std::string err, warn_text;
    bool ok = false;
    const size_t n = bytes.size();
    if (n >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0) {
      // Binary glTF: a 12-byte header (magic, version, total length), then chunks of
      // (length, type, data), the first one JSON (glTF 2.0 §4.4.2 "Header", §4.4.3 "Chunks").
      // tinygltf checks the chunks, but answers a short file with a bare "Invalid glTF binary."
      // and does not look at the version; these are the messages a user can act on.
      if (n < 12)
        return fail("truncated .glb: " + std::to_string(n) + " bytes, less than its 12-byte header");
      const uint32_t version = read_le32(&bytes[4]), length = read_le32(&bytes[8]);
      if (version != 2) {
        return fail(".glb container version " + std::to_string(version) +
                    "; only version 2 (glTF 2.0) is supported");
      }
      if (length > n) {
        return fail("truncated .glb: the header declares " + std::to_string(length) +
                    " bytes, the file has " + std::to_string(n));
      }
      if (length < 20)
        return fail("truncated .glb: " + std::to_string(length) + " bytes leave no room for the JSON chunk");
      const uint32_t json_length = read_le32(&bytes[12]), json_type = read_le32(&bytes[16]);
      if (json_type != 0x4E4F534Au) return fail("invalid .glb: the first chunk is not JSON");
      if (uint64_t(json_length) + 20 > length) {
        return fail("truncated .glb: the JSON chunk (" + std::to_string(json_length) +
                    " bytes) runs past the end of the " + std::to_string(length) + "-byte file");
      }
      if (length < n) warn(std::to_string(n - length) + " bytes after the end of the .glb ignored");
      ok = loader.LoadBinaryFromMemory(&model_, &err, &warn_text, bytes.data(), length, base);
    } else {
      size_t i = 0;
      if (n >= 3 && bytes[0] == 0xEF && bytes[1] == 0xBB && bytes[2] == 0xBF) i = 3;  // UTF-8 BOM
      while (i < n && std::isspace(bytes[i])) ++i;
      if (i == n || bytes[i] != '{') {
        return fail("not a glTF file: neither binary glTF (.glb, magic 'glTF') nor a JSON object (.gltf)");
      }
      ok = loader.LoadASCIIFromString(&model_, &err, &warn_text, reinterpret_cast<const char*>(bytes.data()),
                                      static_cast<unsigned int>(n), base);
    }
    if (!ok) {
      if (err.empty()) return fail("cannot parse the glTF file");
      // With external images left to decode_image, tinygltf reads only buffers from files.
      const bool file = err.compare(0, 5, "File ") == 0;
      return fail((file ? "external buffer: " : "") + clean_message(err));
    }
    // tinygltf reports some problems that it then works around (a property of the wrong
    // type, ...) in `err` while still succeeding: those are warnings here.
    if (!err.empty()) warn(clean_message(err));
    if (!warn_text.empty()) warn(clean_message(warn_text));
    return true;
  }

  // glTF 2.0 §3.12 "Specifying Extensions": extensionsRequired lists the extensions needed to
  // load or render the asset, so one that archwave does not implement makes the file an error.
  bool check_extensions() {
    static const std::set<std::string> supported = {
        "KHR_texture_transform",  "KHR_materials_emissive_strength",
        "KHR_materials_ior",      "KHR_materials_transmission",
        "KHR_materials_volume",   "KHR_materials_clearcoat",
        "KHR_materials_specular", "KHR_materials_unlit",
        "KHR_mesh_quantization"};
    for (const std::string& e : model_.extensionsRequired) {
      if (!supported.count(e))
        return fail("the file requires the extension " + e + ", which archwave does not support");
    }
    // Extensions used but not required have a fallback in the file; say which are ignored.
    // (Unsupported material extensions are named per material, by convert_material.)
    for (const std::string& e : model_.extensionsUsed) {
      if (e == "KHR_lights_punctual") {
        warn("KHR_lights_punctual lights are not imported");
      } else if (!supported.count(e) && e.compare(0, 14, "KHR_materials_") != 0) {
        warn("the extension " + e + " is not supported (ignored)");
      }
    }
    if (!model_.animations.empty()) warn("animations are ignored (the nodes' static transforms are used)");
    if (!model_.skins.empty()) {
      warn("skins are ignored (skinned meshes are placed by their nodes' transforms, unposed)");
    }
    return true;
  }

  // ---- accessors ----------------------------------------------------------------------------

  static int component_size(int type) {
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_BYTE:
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return 1;
      case TINYGLTF_COMPONENT_TYPE_SHORT:
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return 2;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return 4;
      default:
        return 0;  // INT (5124) and DOUBLE (5130) are not glTF 2.0 types (§3.6.2.2)
    }
  }

  static const char* type_name(int type) {
    switch (type) {
      case TINYGLTF_TYPE_SCALAR:
        return "SCALAR";
      case TINYGLTF_TYPE_VEC2:
        return "VEC2";
      case TINYGLTF_TYPE_VEC3:
        return "VEC3";
      case TINYGLTF_TYPE_VEC4:
        return "VEC4";
      case TINYGLTF_TYPE_MAT2:
        return "MAT2";
      case TINYGLTF_TYPE_MAT3:
        return "MAT3";
      case TINYGLTF_TYPE_MAT4:
        return "MAT4";
      default:
        return "an unknown type";
    }
  }

  // One component as a double. Normalised integers follow the table of glTF 2.0 §3.11
  // "Animations" (the conversion that §3.7.2.1 means by "normalized" texture coordinates):
  // f = max(c / (2^(b-1) - 1), -1) signed, c / (2^b - 1) unsigned.
  static double decode_component(const unsigned char* p, int type, bool normalized) {
    switch (type) {
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        const int8_t c = static_cast<int8_t>(p[0]);
        return normalized ? std::max(c / 127.0, -1.0) : double(c);
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return normalized ? p[0] / 255.0 : double(p[0]);
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t c;
        std::memcpy(&c, p, 2);
        return normalized ? std::max(c / 32767.0, -1.0) : double(c);
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t c;
        std::memcpy(&c, p, 2);
        return normalized ? c / 65535.0 : double(c);
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t c;
        std::memcpy(&c, p, 4);
        return double(c);
      }
      default: {
        float f;
        std::memcpy(&f, p, 4);
        return double(f);
      }
    }
  }

  // The bytes [offset, offset + length) of a bufferView, checked against its buffer. `user`
  // names what uses the view, for the message.
  bool view_bytes(int view_index, const std::string& user, const unsigned char** data, size_t* length) {
    if (view_index < 0 || size_t(view_index) >= model_.bufferViews.size()) {
      return fail(user + ": bufferView " + std::to_string(view_index) + " does not exist (the file has " +
                  std::to_string(model_.bufferViews.size()) + ")");
    }
    const tinygltf::BufferView& v = model_.bufferViews[size_t(view_index)];
    if (v.buffer < 0 || size_t(v.buffer) >= model_.buffers.size()) {
      return fail("bufferView " + std::to_string(view_index) + ": buffer " + std::to_string(v.buffer) +
                  " does not exist (the file has " + std::to_string(model_.buffers.size()) + ")");
    }
    const std::vector<unsigned char>& b = model_.buffers[size_t(v.buffer)].data;
    if (v.byteOffset > b.size() || v.byteLength > b.size() - v.byteOffset) {
      return fail("bufferView " + std::to_string(view_index) + ": bytes [" + std::to_string(v.byteOffset) +
                  ", " + std::to_string(uint64_t(v.byteOffset) + v.byteLength) +
                  ") run past the end of buffer " + std::to_string(v.buffer) + ", which has " +
                  std::to_string(b.size()) + " bytes");
    }
    *data = b.data() + v.byteOffset;
    *length = v.byteLength;
    return true;
  }

  // Whether `count` elements of `elem` bytes, `stride` apart, from `offset` fit in `length`
  // bytes (without overflow for any count).
  static bool fits(uint64_t offset, uint64_t count, uint64_t stride, uint64_t elem, uint64_t length) {
    if (count == 0) return offset <= length;
    if (offset > length || length - offset < elem) return false;
    return count - 1 <= (length - offset - elem) / stride;
  }

  // An accessor checked against the bytes that exist (glTF 2.0 §3.6.2 "Accessors"), read one
  // element at a time: a primitive decodes only the vertices its triangles use, so primitives
  // that share one large vertex accessor do not each decode all of it.
  struct Accessor {
    std::string name;                     // "accessor 3 (POSITION of mesh ...)", for messages
    const unsigned char* data = nullptr;  // element 0; null: no bufferView, all zeros
    uint64_t stride = 0, count = 0;
    int comps = 0, csize = 0, ctype = 0;
    bool normalized = false;
    std::map<uint64_t, const unsigned char*> sparse;  // element -> its replacement's bytes
  };

  // Opens accessor `ai`, checking everything it promises. `what` names the use. Only vertex
  // attributes honour bufferView.byteStride; other data (indices) is tightly packed (§3.6.2.1).
  bool open_accessor(int ai, int want_type, const std::string& what, Accessor* r,
                     bool vertex_attribute = true) {
    if (ai < 0 || size_t(ai) >= model_.accessors.size()) {
      return fail(what + ": accessor " + std::to_string(ai) + " does not exist (the file has " +
                  std::to_string(model_.accessors.size()) + ")");
    }
    const tinygltf::Accessor& a = model_.accessors[size_t(ai)];
    r->name = "accessor " + std::to_string(ai) + " (" + what + ")";
    if (a.type != want_type) {
      return fail(r->name + ": type " + type_name(a.type) + ", expected " + type_name(want_type));
    }
    r->csize = component_size(a.componentType);
    if (r->csize == 0) {
      return fail(r->name + ": componentType " + std::to_string(a.componentType) + " is not a glTF 2.0 type");
    }
    if (a.normalized && (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
                         a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)) {
      return fail(r->name + ": 'normalized' is not allowed for float and unsigned int components");
    }
    r->ctype = a.componentType;
    r->normalized = a.normalized;
    r->comps = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
    const uint64_t elem = uint64_t(r->csize) * uint64_t(r->comps);
    r->count = a.count;
    if (r->count > std::numeric_limits<uint32_t>::max()) {
      return fail(r->name + ": count " + std::to_string(r->count) + " is more than 2^32 - 1 elements");
    }
    if (a.bufferView < 0 && r->count > kMaxZeroFilledCount) {
      return fail(r->name + ": count " + std::to_string(r->count) +
                  " without a bufferView (zeros) is implausibly large");
    }
    if (a.bufferView >= 0) {
      const unsigned char* data;
      size_t length;
      if (!view_bytes(a.bufferView, r->name, &data, &length)) return false;
      const size_t stride_given = vertex_attribute ? model_.bufferViews[size_t(a.bufferView)].byteStride : 0;
      r->stride = stride_given ? stride_given : elem;
      if (r->stride < elem) {
        return fail(r->name + ": bufferView " + std::to_string(a.bufferView) + " has byteStride " +
                    std::to_string(r->stride) + ", less than the element size " + std::to_string(elem));
      }
      if (!fits(a.byteOffset, r->count, r->stride, elem, length)) {
        return fail(r->name + ": " + std::to_string(r->count) + " elements of " + std::to_string(elem) +
                    " bytes (stride " + std::to_string(r->stride) + ") from byte " +
                    std::to_string(a.byteOffset) + " need more than the " + std::to_string(length) +
                    " bytes of bufferView " + std::to_string(a.bufferView));
      }
      r->data = data + a.byteOffset;
    }
    if (a.sparse.isSparse) {
      // glTF 2.0 §3.6.2.3 "Sparse Accessors": `count` elements at the given indices replace
      // the base values (zeros without a bufferView); indices are below the accessor's count.
      const auto& s = a.sparse;
      if (s.count < 0 || uint64_t(s.count) > r->count) {
        return fail(r->name + ": sparse.count " + std::to_string(s.count) + " is not in [0, " +
                    std::to_string(r->count) + "]");
      }
      const int itype = s.indices.componentType;
      if (itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
          itype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
        return fail(r->name + ": sparse.indices.componentType " + std::to_string(itype) +
                    " is not an unsigned integer type");
      }
      const uint64_t isize = uint64_t(component_size(itype));
      if (s.indices.byteOffset < 0 || s.values.byteOffset < 0) {
        return fail(r->name + ": a sparse byteOffset is negative");
      }
      const unsigned char *idata, *vdata;
      size_t ilength, vlength;
      if (!view_bytes(s.indices.bufferView, r->name + " sparse.indices", &idata, &ilength)) return false;
      if (!view_bytes(s.values.bufferView, r->name + " sparse.values", &vdata, &vlength)) return false;
      if (!fits(uint64_t(s.indices.byteOffset), uint64_t(s.count), isize, isize, ilength) ||
          !fits(uint64_t(s.values.byteOffset), uint64_t(s.count), elem, elem, vlength)) {
        return fail(r->name + ": the sparse indices or values need more bytes than their bufferViews have");
      }
      for (uint64_t k = 0; k < uint64_t(s.count); ++k) {
        const double target =
            decode_component(idata + uint64_t(s.indices.byteOffset) + k * isize, itype, false);
        if (target >= double(r->count)) {
          return fail(r->name + ": sparse index " + fmt(target) + " is not below the count " +
                      std::to_string(r->count));
        }
        r->sparse[uint64_t(target)] = vdata + uint64_t(s.values.byteOffset) + k * elem;
      }
    }
    return true;
  }

  // Element i (below r.count) into out[0 .. comps). glTF 2.0 §3.6.2.2: NaN and infinities
  // MUST NOT be present; one is an error naming the accessor and the element.
  bool element(const Accessor& r, uint64_t i, double* out) {
    const unsigned char* p = r.data ? r.data + i * r.stride : nullptr;
    if (!r.sparse.empty()) {
      auto it = r.sparse.find(i);
      if (it != r.sparse.end()) p = it->second;
    }
    for (int c = 0; c < r.comps; ++c) {
      out[c] = p ? decode_component(p + c * r.csize, r.ctype, r.normalized) : 0.0;
      if (!std::isfinite(out[c])) {
        return fail(r.name + ": element " + std::to_string(i) + " has a value that is not finite");
      }
    }
    return true;
  }

  // Indices: SCALAR unsigned byte, short or int, not normalised, each below the vertex count
  // (glTF 2.0 §3.7.2.1).
  bool read_indices(int ai, size_t vertex_count, const std::string& what, std::vector<uint32_t>* out) {
    Accessor r;
    if (!open_accessor(ai, TINYGLTF_TYPE_SCALAR, what, &r, false)) return false;
    if (r.ctype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        r.ctype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        r.ctype != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
      return fail(r.name + ": componentType " + std::to_string(r.ctype) +
                  " is not an unsigned byte, short or int");
    }
    if (r.normalized) return fail(r.name + ": indices cannot be normalized");
    out->resize(size_t(r.count));
    for (uint64_t i = 0; i < r.count; ++i) {
      double v;
      if (!element(r, i, &v)) return false;
      if (v >= double(vertex_count)) {
        return fail(r.name + ": index " + fmt(v) + " at position " + std::to_string(i) +
                    " is out of range: the primitive has " + std::to_string(vertex_count) + " vertices");
      }
      (*out)[size_t(i)] = static_cast<uint32_t>(v);
    }
    return true;
  }

  // ---- materials ----------------------------------------------------------------------------

  void mat_warn(MaterialState& ms, const std::string& message) {
    const std::string full = ms.name + ": " + message;
    if (ms.warned.insert(full).second) warn(full);
  }

  // A TextureRef's multiplier is one number; glTF's colour factors are RGB. Exact for a grey
  // factor; otherwise the luminance (Rec. 709) is used, with a warning.
  float colour_multiplier(MaterialState& ms, const glm::dvec3& f, const char* what) {
    if (f.x == f.y && f.y == f.z) return float(f.x);
    const double lum = 0.2126 * f.x + 0.7152 * f.y + 0.0722 * f.z;
    mat_warn(ms, std::string(what) + " [" + fmt(f.x) + ", " + fmt(f.y) + ", " + fmt(f.z) +
                     "] multiplies a texture; a texture's multiplier is one number, its luminance " +
                     fmt(lum) + " is used");
    return float(lum);
  }

  // Binds `key` to the texture of `info`. Returns false only on an error; an absent texture
  // (index -1) binds nothing. srgb: the colour space the use needs (glTF 2.0 §3.9.2: base colour
  // and emissive textures are sRGB, the others linear).
  bool bind(MaterialState& ms, const TexInfo& info, const char* property, bool srgb, const std::string& key,
            int channel, float multiplier, float offset, bool* bound = nullptr) {
    if (bound) *bound = false;
    if (!info.valid) return fail(ms.name + ": " + property + " " + info.problem);
    if (info.index < 0) return true;
    if (size_t(info.index) >= model_.textures.size()) {
      return fail(ms.name + ": " + property + " refers to texture " + std::to_string(info.index) +
                  ", but the file has " + std::to_string(model_.textures.size()) + " textures");
    }
    if (info.tex_coord > 1) {
      mat_warn(ms, std::string(property) + " uses texCoord " + std::to_string(info.tex_coord) +
                       "; archwave meshes carry two UV sets (TEXCOORD_0 and TEXCOORD_1), TEXCOORD_0 is used");
    }
    uint32_t id = 0;
    bool usable = false;
    if (!texture_for(ms, info, property, srgb, &id, &usable)) return false;
    if (!usable) return true;
    TextureRef r;
    r.texture = id;
    r.channel = channel;
    r.multiplier = multiplier;
    r.offset = offset;
    r.uv_set = info.tex_coord == 1 ? 1 : 0;
    ms.bindings[key] = r;
    if (bound) *bound = true;
    return true;
  }

  // The TextureDesc for a textureInfo in a colour space: decoded once per (image, colour
  // space), copied for each further sampler or UV transform.
  bool texture_for(MaterialState& ms, const TexInfo& info, const char* property, bool srgb, uint32_t* id,
                   bool* usable) {
    const tinygltf::Texture& tex = model_.textures[size_t(info.index)];
    const std::string tex_name = "texture " + std::to_string(info.index);
    if (tex.source < 0) {
      // glTF 2.0 §3.8.2: without `source` the image comes from an extension (KTX2, WebP, ...).
      mat_warn(
          ms, std::string(property) + ": " + tex_name +
                  " has no PNG/JPEG source (only an extension's image format); the input is left untextured");
      return true;
    }
    if (size_t(tex.source) >= model_.images.size()) {
      return fail(tex_name + ": image " + std::to_string(tex.source) + " does not exist (the file has " +
                  std::to_string(model_.images.size()) + ")");
    }
    TextureDesc t;
    t.type = TextureDesc::Type::Image;
    t.colorspace = srgb ? TextureDesc::ColorSpace::Srgb : TextureDesc::ColorSpace::Linear;
    if (!sampler_wrap(ms, tex.sampler, tex_name, &t.wrap)) return false;
    set_transform(info, &t);

    const TextureKey key{info.index, srgb, t.offset.x, t.offset.y, t.scale.x, t.scale.y, t.rotation};
    // The wrap mode belongs to the texture, so it is part of the key through info.index.
    auto it = texture_ids_.find(key);
    if (it != texture_ids_.end()) {
      *id = it->second;
      *usable = true;
      return true;
    }
    const int variant = variants_[info.index]++;
    t.name = file_name_ + "#" + tex_name + (variant ? " (" + std::to_string(variant + 1) + ")" : "");

    const std::pair<int, bool> image_key(tex.source, srgb);
    auto dec = decoded_.find(image_key);
    if (dec != decoded_.end()) {
      t.source = out_->textures[dec->second].source;
      copy_decoded_image(out_->textures[dec->second], &t);
    } else {
      if (!decode_image(tex.source, &t)) return false;
      decoded_[image_key] = out_->textures.size();
    }
    *id = static_cast<uint32_t>(out_->textures.size());
    out_->textures.push_back(std::move(t));
    texture_ids_[key] = *id;
    *usable = true;
    return true;
  }

  bool decode_image(int image_index, TextureDesc* t) {
    const tinygltf::Image& img = model_.images[size_t(image_index)];
    const std::string name = label("image", image_index, img.name);
    std::string err;
    if (img.bufferView >= 0) {
      const unsigned char* data;
      size_t length;
      if (!view_bytes(img.bufferView, name, &data, &length)) return false;
      t->source = file_name_ + ", image " + std::to_string(image_index);
      if (!decode_texture_image(data, length, t, &err)) return fail(name + ": " + err);
      return true;
    }
    if (!img.image.empty()) {  // a data URI, kept by keep_encoded_image
      t->source = file_name_ + ", image " + std::to_string(image_index);
      if (!decode_texture_image(img.image.data(), img.image.size(), t, &err)) return fail(name + ": " + err);
      return true;
    }
    if (img.uri.compare(0, 5, "data:") == 0) {
      // tinygltf decodes only the media types it knows (PNG, JPEG, ...) and base64.
      return fail(name + ": a data URI of a media type or encoding that cannot be read (" +
                  img.uri.substr(0, std::min<size_t>(img.uri.find(','), 40)) + ")");
    }
    if (img.uri.empty()) return fail(name + ": neither a bufferView nor a uri");
    const fs::path file = fs::path(fs_ctx_.prefix) / percent_decode(img.uri);
    t->source = file.lexically_normal().string();
    if (!load_texture_file(t->source, t, &err)) return fail(name + " ('" + img.uri + "'): " + err);
    return true;
  }

  // glTF 2.0 §3.8.4.3 "Wrapping"; a texture without a sampler repeats (§3.8.2).
  bool sampler_wrap(MaterialState& ms, int sampler, const std::string& tex_name, TextureDesc::Wrap* wrap) {
    *wrap = TextureDesc::Wrap::Repeat;
    if (sampler < 0) return true;
    if (size_t(sampler) >= model_.samplers.size()) {
      return fail(tex_name + ": sampler " + std::to_string(sampler) + " does not exist (the file has " +
                  std::to_string(model_.samplers.size()) + ")");
    }
    const tinygltf::Sampler& s = model_.samplers[size_t(sampler)];
    auto convert = [&](int mode, TextureDesc::Wrap* w) {
      switch (mode) {
        case TINYGLTF_TEXTURE_WRAP_REPEAT:
          *w = TextureDesc::Wrap::Repeat;
          return true;
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
          *w = TextureDesc::Wrap::Clamp;
          return true;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
          *w = TextureDesc::Wrap::Mirror;
          return true;
        default:
          return false;
      }
    };
    TextureDesc::Wrap ws, wt;
    if (!convert(s.wrapS, &ws) || !convert(s.wrapT, &wt)) {
      return fail("sampler " + std::to_string(sampler) + ": wrap mode " + std::to_string(s.wrapS) + "/" +
                  std::to_string(s.wrapT) + " is not REPEAT, CLAMP_TO_EDGE or MIRRORED_REPEAT");
    }
    if (ws != wt) {
      mat_warn(ms, tex_name + ": sampler " + std::to_string(sampler) +
                       " wraps S and T differently; archwave has one wrap mode per texture, wrapS is used");
    }
    *wrap = ws;
    return true;
  }

  // KHR_texture_transform in glTF's UV space (origin top left, v down) is
  //   uv_g' = o + R_g S uv_g,  R_g = [[cos r, sin r], [-sin r, cos r]],
  // the rotation that the extension's example and implementations apply (offset [0, 1],
  // rotation pi/2, scale 0.5 picks the lower left quadrant). archwave's UV is uv = F(uv_g) with
  // F(u, v) = (u, 1 - v) = D uv_g + e, D = diag(1, -1), e = (0, 1), and TextureDesc's transform
  // is uv' = R(rotation) S uv + offset with R the counter-clockwise rotation. The lookup at
  // F(uv_g') for uv_g = F(uv) is
  //   F(o + R_g S (D uv + e)) = (D R_g D) S uv + D (o + R_g S e) + e,
  // and D R_g D = [[cos r, -sin r], [sin r, cos r]] = R(r): the same angle, counter-clockwise in
  // archwave's V-up space; scale unchanged; offset = D o + D R_g (0, s_v) + e
  //   = (o_u + s_v sin r, 1 - o_v - s_v cos r).
  static void set_transform(const TexInfo& info, TextureDesc* t) {
    if (!info.transformed) return;
    const double r = info.rotation, c = std::cos(r), s = std::sin(r);
    t->scale = glm::vec2(glm::dvec2(info.scale));
    t->rotation = float(r * (180.0 / kPi));
    t->offset =
        glm::vec2(float(info.offset.x + info.scale.y * s), float(1.0 - info.offset.y - info.scale.y * c));
  }

  const tinygltf::Value* extension(const tinygltf::Material& g, const char* name) {
    auto it = g.extensions.find(name);
    return it == g.extensions.end() ? nullptr : &it->second;
  }

  // A number of an extension object, `def` when absent; a value of the wrong type is an error.
  bool ext_number(const MaterialState& ms, const tinygltf::Value* ext, const char* ext_name, const char* key,
                  double def, double* out) {
    *out = def;
    const tinygltf::Value* v = ext ? member(*ext, key) : nullptr;
    if (!v) return true;
    if (!v->IsNumber() || !std::isfinite(v->GetNumberAsDouble())) {
      return fail(ms.name + ": " + ext_name + "." + key + " is not a finite number");
    }
    *out = v->GetNumberAsDouble();
    return true;
  }

  bool ext_colour(const MaterialState& ms, const tinygltf::Value* ext, const char* ext_name, const char* key,
                  glm::dvec3 def, glm::dvec3* out) {
    *out = def;
    const tinygltf::Value* v = ext ? member(*ext, key) : nullptr;
    if (!v) return true;
    if (!v->IsArray() || v->ArrayLen() != 3)
      return fail(ms.name + ": " + ext_name + "." + key + " is not an array of 3 numbers");
    for (int i = 0; i < 3; ++i) {
      if (!v->Get(i).IsNumber() || !std::isfinite(v->Get(i).GetNumberAsDouble())) {
        return fail(ms.name + ": " + ext_name + "." + key + " is not an array of 3 finite numbers");
      }
      (*out)[i] = v->Get(i).GetNumberAsDouble();
    }
    return true;
  }

  // A factor documented as [lo, hi]: clamped, with a warning.
  double clamp_factor(MaterialState& ms, const char* what, double v, double lo, double hi) {
    if (v < lo || v > hi) {
      mat_warn(ms,
               std::string(what) + " " + fmt(v) + " is outside [" + fmt(lo) + ", " + fmt(hi) + "], clamped");
      return std::min(std::max(v, lo), hi);
    }
    return v;
  }

  bool convert_materials() {
    const size_t n = model_.materials.size();
    out_->materials.reserve(n);
    out_->material_names.reserve(n);
    out_->bindings.reserve(n);
    for (size_t i = 0; i < n; ++i) {
      MaterialState ms;
      ms.index = int(i);
      ms.name = label("material", int(i), model_.materials[i].name);
      MaterialDesc m;
      if (!convert_material(model_.materials[i], ms, &m)) return false;
      out_->materials.push_back(m);
      out_->material_names.push_back(model_.materials[i].name.empty() ? "material " + std::to_string(i)
                                                                      : model_.materials[i].name);
      out_->bindings.push_back(std::move(ms.bindings));
    }
    return true;
  }

  // glTF's metallic-roughness material (glTF 2.0 §3.9.2, Appendix B) and its KHR_materials_*
  // extensions as the Architectural material (docs/material.md). Table and reasons: docs/gltf.md.
  bool convert_material(const tinygltf::Material& g, MaterialState& ms, MaterialDesc* out) {
    MaterialDesc m;
    const tinygltf::PbrMetallicRoughness& pbr = g.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() != 4)
      return fail(ms.name + ": baseColorFactor is not an array of 4 numbers");
    glm::dvec4 base;
    for (int i = 0; i < 4; ++i) {
      base[i] = pbr.baseColorFactor[size_t(i)];
      if (!std::isfinite(base[i])) return fail(ms.name + ": baseColorFactor is not finite");
    }
    for (int i = 0; i < 4; ++i) base[i] = clamp_factor(ms, "baseColorFactor", base[i], 0.0, 1.0);
    if (!std::isfinite(pbr.metallicFactor) || !std::isfinite(pbr.roughnessFactor)) {
      return fail(ms.name + ": metallicFactor or roughnessFactor is not finite");
    }
    const double metallic = clamp_factor(ms, "metallicFactor", pbr.metallicFactor, 0.0, 1.0);
    const double roughness = clamp_factor(ms, "roughnessFactor", pbr.roughnessFactor, 0.0, 1.0);
    const TexInfo base_tex = tex_info(pbr.baseColorTexture);
    const TexInfo mr_tex = tex_info(pbr.metallicRoughnessTexture);
    const glm::dvec3 base_rgb(base);

    // Extensions this conversion does not model: named once each.
    for (const char* ignored :
         {"KHR_materials_sheen", "KHR_materials_iridescence", "KHR_materials_anisotropy",
          "KHR_materials_dispersion", "KHR_materials_diffuse_transmission",
          "KHR_materials_pbrSpecularGlossiness"}) {
      if (extension(g, ignored)) mat_warn(ms, std::string(ignored) + " is not supported (ignored)");
    }
    const tinygltf::Value* unlit = extension(g, "KHR_materials_unlit");
    const tinygltf::Value* ior_ext = extension(g, "KHR_materials_ior");
    const tinygltf::Value* specular = extension(g, "KHR_materials_specular");
    const tinygltf::Value* transmission = extension(g, "KHR_materials_transmission");
    const tinygltf::Value* volume = extension(g, "KHR_materials_volume");
    const tinygltf::Value* clearcoat = extension(g, "KHR_materials_clearcoat");
    const tinygltf::Value* strength_ext = extension(g, "KHR_materials_emissive_strength");

    // Base colour: the diffuse colour, and through `metal` the reflection's tint.
    m.diffuse.color = glm::vec3(base_rgb);
    m.diffuse.weight = 1.0f;
    m.diffuse.roughness = 0.0f;
    bool base_bound = false;
    if (base_tex.index >= 0) {
      if (!bind(ms, base_tex, "baseColorTexture", true, "diffuse.color", -1,
                colour_multiplier(ms, base_rgb, "baseColorFactor"), 0.0f, &base_bound)) {
        return false;
      }
    }

    // Metalness: archwave's `metal` is a switch for the whole material.
    m.metal = metallic >= 0.5;
    if (mr_tex.index >= 0 && metallic > 0.0) {
      mat_warn(
          ms,
          "metallicRoughnessTexture's metalness (B) cannot switch the material per texel; metallicFactor " +
              fmt(metallic) + " makes it " + (m.metal ? "a metal" : "a dielectric"));
    } else if (metallic > 0.0 && metallic < 1.0) {
      mat_warn(ms, "metallicFactor " + fmt(metallic) + " is taken as " + (m.metal ? "metal" : "dielectric") +
                       " (archwave's metal is on or off)");
    }

    // Specular reflection: GGX with glossiness g = 1 - roughness (archwave's alpha = (1 - g)^2,
    // glTF's alpha = roughness^2, Appendix B.2.3), weight 1, Fresnel from the IOR.
    m.reflection.weight = 1.0f;
    m.reflection.color = glm::vec3(1.0f);
    m.reflection.brdf = Brdf::Ggx;
    m.reflection.glossiness = float(1.0 - roughness);
    if (!bind(ms, mr_tex, "metallicRoughnessTexture", false, "reflection.glossiness", 1, float(-roughness),
              1.0f)) {
      return false;
    }

    double ior = 1.5;
    if (!ext_number(ms, ior_ext, "KHR_materials_ior", "ior", 1.5, &ior)) return false;
    bool fresnel_one = false;
    if (ior == 0.0) {
      fresnel_one = true;  // KHR_materials_ior: 0 means an infinite IOR, Fresnel 1 everywhere
      ior = 1.5;
    } else if (ior < 1.0) {
      mat_warn(ms, "KHR_materials_ior.ior " + fmt(ior) + " is below 1; 1.5 is used");
      ior = 1.5;
    }
    m.refraction.ior = float(ior);
    if (m.metal || fresnel_one) {
      // A metal's reflectance at normal incidence is the base colour (glTF 2.0 Appendix B.2.1);
      // `metal` multiplies the reflection by the diffuse colour, so the Fresnel factor itself
      // is 1 at every angle: the artist curve with facing = perpendicular = 1.
      m.reflection.fresnel.use_ior = false;
      m.reflection.fresnel.facing = 1.0f;
      m.reflection.fresnel.perpendicular = 1.0f;
    } else {
      m.reflection.fresnel.use_ior = true;
      m.reflection.fresnel.lock_to_refraction_ior = true;
      m.reflection.fresnel.ior = float(ior);
    }

    // KHR_materials_specular: the dielectric's specular strength and F0 colour.
    if (specular) {
      if (m.metal) {
        mat_warn(ms, "KHR_materials_specular applies to dielectrics only; ignored for this metal");
      } else {
        double factor;
        glm::dvec3 colour;
        if (!ext_number(ms, specular, "KHR_materials_specular", "specularFactor", 1.0, &factor)) return false;
        if (!ext_colour(ms, specular, "KHR_materials_specular", "specularColorFactor", glm::dvec3(1.0),
                        &colour)) {
          return false;
        }
        factor = clamp_factor(ms, "specularFactor", factor, 0.0, 1.0);
        for (int i = 0; i < 3; ++i) colour[i] = clamp_factor(ms, "specularColorFactor", colour[i], 0.0, 1.0);
        m.reflection.weight = float(factor);
        m.reflection.color = glm::vec3(colour);
        if (!bind(ms, tex_info(member(*specular, "specularTexture")), "specularTexture", false,
                  "reflection.weight", 3, float(factor), 0.0f)) {
          return false;
        }
        const TexInfo colour_tex = tex_info(member(*specular, "specularColorTexture"));
        if (colour_tex.index >= 0 || !colour_tex.valid) {
          if (!bind(ms, colour_tex, "specularColorTexture", true, "reflection.color", -1,
                    colour_multiplier(ms, colour, "specularColorFactor"), 0.0f)) {
            return false;
          }
        }
      }
    }

    // KHR_materials_transmission (+ KHR_materials_volume): refraction through the surface.
    if (transmission) {
      double factor;
      if (!ext_number(ms, transmission, "KHR_materials_transmission", "transmissionFactor", 0.0, &factor))
        return false;
      factor = clamp_factor(ms, "transmissionFactor", factor, 0.0, 1.0);
      const TexInfo t_tex = tex_info(member(*transmission, "transmissionTexture"));
      if (m.metal && (factor > 0.0 || t_tex.index >= 0)) {
        mat_warn(ms, "KHR_materials_transmission applies to dielectrics only; ignored for this metal");
      } else if (factor > 0.0) {
        m.refraction.weight = float(factor);
        m.refraction.color = glm::vec3(base_rgb);  // transmitted light is tinted by the base colour
        m.refraction.glossiness = float(1.0 - roughness);
        if (!bind(ms, t_tex, "transmissionTexture", false, "refraction.weight", 0, float(factor), 0.0f))
          return false;
        if (base_bound) ms.bindings["refraction.color"] = ms.bindings["diffuse.color"];
        if (ms.bindings.count("reflection.glossiness")) {
          ms.bindings["refraction.glossiness"] = ms.bindings["reflection.glossiness"];
        }
        // Without KHR_materials_volume, or with thickness 0, the surface is a thin wall.
        double thickness = 0.0, distance = std::numeric_limits<double>::infinity();
        glm::dvec3 attenuation(1.0);
        if (!ext_number(ms, volume, "KHR_materials_volume", "thicknessFactor", 0.0, &thickness)) return false;
        if (volume && member(*volume, "attenuationDistance") &&
            !ext_number(ms, volume, "KHR_materials_volume", "attenuationDistance", distance, &distance)) {
          return false;
        }
        if (!ext_colour(ms, volume, "KHR_materials_volume", "attenuationColor", glm::dvec3(1.0),
                        &attenuation)) {
          return false;
        }
        m.refraction.thin_walled = !(thickness > 0.0);
        // attenuationColor reached at attenuationDistance, exponentially: the fog's end colour
        // (docs/material.md §3.7: transmittance end_color^(d / distance)).
        if (!m.refraction.thin_walled && distance > 0.0 && std::isfinite(distance)) {
          m.refraction.fog.enable = true;
          m.refraction.fog.distance = float(distance);
          m.refraction.fog.use_end_color = true;
          for (int i = 0; i < 3; ++i)
            attenuation[i] = clamp_factor(ms, "attenuationColor", attenuation[i], 0.0, 1.0);
          m.refraction.fog.end_color = glm::vec3(attenuation);
        }
      }
    }

    // KHR_materials_clearcoat: a second, white, GGX reflection with its own IOR of 1.5.
    if (clearcoat) {
      double factor, cc_roughness;
      if (!ext_number(ms, clearcoat, "KHR_materials_clearcoat", "clearcoatFactor", 0.0, &factor))
        return false;
      if (!ext_number(ms, clearcoat, "KHR_materials_clearcoat", "clearcoatRoughnessFactor", 0.0,
                      &cc_roughness)) {
        return false;
      }
      factor = clamp_factor(ms, "clearcoatFactor", factor, 0.0, 1.0);
      cc_roughness = clamp_factor(ms, "clearcoatRoughnessFactor", cc_roughness, 0.0, 1.0);
      if (factor > 0.0) {
        m.reflection2.weight = float(factor);
        m.reflection2.color = glm::vec3(1.0f);
        m.reflection2.brdf = Brdf::Ggx;
        m.reflection2.glossiness = float(1.0 - cc_roughness);
        m.reflection2.fresnel.use_ior = true;
        m.reflection2.fresnel.lock_to_refraction_ior = false;
        m.reflection2.fresnel.ior = 1.5f;
        if (!bind(ms, tex_info(member(*clearcoat, "clearcoatTexture")), "clearcoatTexture", false,
                  "reflection2.weight", 0, float(factor), 0.0f) ||
            !bind(ms, tex_info(member(*clearcoat, "clearcoatRoughnessTexture")), "clearcoatRoughnessTexture",
                  false, "reflection2.glossiness", 1, float(-cc_roughness), 1.0f)) {
          return false;
        }
        if (member(*clearcoat, "clearcoatNormalTexture")) {
          mat_warn(ms, "clearcoatNormalTexture is not supported yet (ignored)");
        }
      }
    }

    // Emission: emissiveFactor x emissiveTexture x KHR_materials_emissive_strength.
    if (g.emissiveFactor.size() != 3) return fail(ms.name + ": emissiveFactor is not an array of 3 numbers");
    glm::dvec3 emissive(g.emissiveFactor[0], g.emissiveFactor[1], g.emissiveFactor[2]);
    for (int i = 0; i < 3; ++i) {
      if (!std::isfinite(emissive[i])) return fail(ms.name + ": emissiveFactor is not finite");
      emissive[i] = clamp_factor(ms, "emissiveFactor", emissive[i], 0.0, 1.0);
    }
    double strength = 1.0;
    if (!ext_number(ms, strength_ext, "KHR_materials_emissive_strength", "emissiveStrength", 1.0,
                    &strength)) {
      return false;
    }
    strength = clamp_factor(ms, "emissiveStrength", strength, 0.0, std::numeric_limits<double>::max());
    m.incandescent.color = glm::vec3(emissive);
    m.incandescent.scale = float(strength);
    const TexInfo emissive_tex = tex_info(g.emissiveTexture);
    if (emissive_tex.index >= 0 && emissive != glm::dvec3(0.0)) {
      if (!bind(ms, emissive_tex, "emissiveTexture", true, "incandescent.color", -1,
                colour_multiplier(ms, emissive, "emissiveFactor"), 0.0f)) {
        return false;
      }
    }

    // KHR_materials_unlit: the base colour as it is, unlit. Approximated by emitting it, with
    // no lobe that would add lighting.
    if (unlit) {
      mat_warn(
          ms,
          "KHR_materials_unlit is approximated: the base colour is emitted (incandescent), no other lobes");
      m.metal = false;
      m.diffuse.weight = 0.0f;
      m.reflection.weight = 0.0f;
      m.reflection2.weight = 0.0f;
      m.refraction.weight = 0.0f;
      m.incandescent.color = glm::vec3(base_rgb);
      m.incandescent.scale = 1.0f;
      for (const char* k : {"diffuse.color", "reflection.glossiness", "reflection.weight", "reflection.color",
                            "reflection2.weight", "reflection2.glossiness", "refraction.weight",
                            "refraction.color", "refraction.glossiness", "incandescent.color"}) {
        ms.bindings.erase(k);
      }
      if (base_bound) {
        if (!bind(ms, base_tex, "baseColorTexture", true, "incandescent.color", -1,
                  colour_multiplier(ms, base_rgb, "baseColorFactor"), 0.0f)) {
          return false;
        }
      }
    }

    // Alpha coverage (glTF 2.0 §3.9.4). archwave's cutout: a value below 0.5 is a hole. MASK is
    // opaque where alpha >= alphaCutoff: the binding maps alpha = cutoff to exactly 0.5 with a
    // line that keeps [0, 1] inside [0, 1] (through (cutoff, 0.5) and (1, 1) for a cutoff up to
    // 0.5, through (0, 0) and (cutoff, 0.5) above), so a renderer that clamps the input to the
    // key's range [0, 1] still thresholds at the cutoff.
    std::string mode = g.alphaMode.empty() ? "OPAQUE" : g.alphaMode;
    double cutoff = g.alphaCutoff;
    if (mode == "BLEND") {
      mat_warn(ms, "alphaMode BLEND is not supported; treated as MASK with alphaCutoff 0.5");
      mode = "MASK";
      cutoff = 0.5;
    } else if (mode != "OPAQUE" && mode != "MASK") {
      mat_warn(ms, "alphaMode '" + mode + "' is not OPAQUE, MASK or BLEND; treated as OPAQUE");
      mode = "OPAQUE";
    }
    if (mode == "MASK") {
      if (!std::isfinite(cutoff)) return fail(ms.name + ": alphaCutoff is not finite");
      if (cutoff <= 0.0) {
        m.cutout_opacity = 1.0f;  // every alpha >= 0 passes
      } else {
        m.cutout_opacity = base.w >= cutoff ? 1.0f : 0.0f;
        if (base_bound) {
          double slope, offset;
          if (cutoff <= 0.5) {
            slope = 0.5 / (1.0 - cutoff);
            offset = 1.0 - slope;
          } else {
            slope = 0.5 / cutoff;
            offset = 0.0;
          }
          TextureRef r = ms.bindings[unlit ? "incandescent.color" : "diffuse.color"];
          r.channel = 3;
          r.multiplier = float(slope * base.w);  // the texel's alpha times the factor's
          r.offset = float(offset);
          ms.bindings["cutout_opacity"] = r;
        }
      }
    }

    // Ignored, or not supported yet.
    if (g.normalTexture.index >= 0) mat_warn(ms, "normalTexture is not supported yet (ignored)");
    // occlusionTexture: ambient occlusion baked for rasterisers; a path tracer computes the
    // occlusion itself, so it is ignored without a word (docs/gltf.md).
    // doubleSided: archwave's surfaces are two-sided already (glTF 2.0 §3.9.5).

    *out = m;
    return true;
  }

  // ---- scene and meshes ---------------------------------------------------------------------

  // A node's local transform (glTF 2.0 §3.5.3): `matrix` (column-major, as glm) or T * R * S.
  bool node_matrix(int ni, glm::dmat4* out) {
    const tinygltf::Node& n = model_.nodes[size_t(ni)];
    const std::string name = label("node", ni, n.name);
    if (!n.matrix.empty()) {
      if (n.matrix.size() != 16)
        return fail(name + ": matrix has " + std::to_string(n.matrix.size()) + " numbers, not 16");
      for (int c = 0; c < 4; ++c) {
        for (int r = 0; r < 4; ++r) (*out)[c][r] = n.matrix[size_t(c * 4 + r)];
      }
      for (int i = 0; i < 16; ++i) {
        if (!std::isfinite(n.matrix[size_t(i)]))
          return fail(name + ": matrix has a value that is not finite");
      }
      // "MUST be decomposable to TRS": in particular affine, bottom row (0, 0, 0, 1).
      if ((*out)[0][3] != 0.0 || (*out)[1][3] != 0.0 || (*out)[2][3] != 0.0 || (*out)[3][3] != 1.0) {
        return fail(name + ": matrix is not affine (its last row is not 0, 0, 0, 1)");
      }
      return true;
    }
    glm::dvec3 t(0.0), s(1.0);
    glm::dquat q(1.0, 0.0, 0.0, 0.0);
    if (!n.translation.empty()) {
      if (n.translation.size() != 3) return fail(name + ": translation is not 3 numbers");
      t = glm::dvec3(n.translation[0], n.translation[1], n.translation[2]);
    }
    if (!n.scale.empty()) {
      if (n.scale.size() != 3) return fail(name + ": scale is not 3 numbers");
      s = glm::dvec3(n.scale[0], n.scale[1], n.scale[2]);
    }
    if (!n.rotation.empty()) {
      if (n.rotation.size() != 4) return fail(name + ": rotation is not a quaternion of 4 numbers");
      // glTF stores XYZW, W the scalar; glm's constructor takes (w, x, y, z).
      q = glm::dquat(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]);
      const double len = glm::length(q);
      if (!(len > 0.0) || !std::isfinite(len)) return fail(name + ": rotation is not a usable quaternion");
      q /= len;  // "a unit quaternion": tolerate the rounding of writers
    }
    for (int i = 0; i < 3; ++i) {
      if (!std::isfinite(t[i]) || !std::isfinite(s[i]))
        return fail(name + ": translation or scale is not finite");
    }
    glm::dmat4 T(1.0), S(1.0);
    T[3] = glm::dvec4(t, 1.0);
    S[0][0] = s.x;
    S[1][1] = s.y;
    S[2][2] = s.z;
    *out = T * glm::mat4_cast(q) * S;
    return true;
  }

  bool import_scene() {
    // The default scene, else scene 0, else every root node (glTF 2.0 §3.5.1: without
    // `scene`, which scene to show is up to the application).
    std::vector<int> roots;
    if (model_.defaultScene >= 0 || !model_.scenes.empty()) {
      const int si = model_.defaultScene >= 0 ? model_.defaultScene : 0;
      if (size_t(si) >= model_.scenes.size()) {
        return fail("scene " + std::to_string(si) + " does not exist (the file has " +
                    std::to_string(model_.scenes.size()) + " scenes)");
      }
      roots = model_.scenes[size_t(si)].nodes;
      if (model_.defaultScene < 0 && model_.scenes.size() > 1) {
        warn("no default scene; scene 0 of " + std::to_string(model_.scenes.size()) + " is imported");
      }
    } else {
      std::vector<char> is_child(model_.nodes.size(), 0);
      for (const tinygltf::Node& n : model_.nodes) {
        for (int c : n.children) {
          if (c >= 0 && size_t(c) < model_.nodes.size()) is_child[size_t(c)] = 1;
        }
      }
      for (size_t i = 0; i < model_.nodes.size(); ++i) {
        if (!is_child[i]) roots.push_back(int(i));
      }
    }

    // Depth first with an explicit stack (a deep chain of nodes cannot overflow the call
    // stack); a node met twice breaks "a set of disjoint strict trees" (§3.5.2) and, in a
    // cycle, would never end.
    struct Item {
      int node;
      glm::dmat4 parent;
      int parent_node;
    };
    std::vector<char> visited(model_.nodes.size(), 0);
    std::vector<Item> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, glm::dmat4(1.0), -1});
    while (!stack.empty()) {
      const Item item = stack.back();
      stack.pop_back();
      if (item.node < 0 || size_t(item.node) >= model_.nodes.size()) {
        return fail(
            (item.parent_node < 0 ? std::string("the scene") : "node " + std::to_string(item.parent_node)) +
            " refers to node " + std::to_string(item.node) + ", but the file has " +
            std::to_string(model_.nodes.size()) + " nodes");
      }
      if (visited[size_t(item.node)]) {
        return fail("node " + std::to_string(item.node) +
                    " is reached twice: the node hierarchy must be a set of disjoint trees without cycles");
      }
      visited[size_t(item.node)] = 1;
      glm::dmat4 local;
      if (!node_matrix(item.node, &local)) return false;
      const glm::dmat4 world = item.parent * local;
      const tinygltf::Node& n = model_.nodes[size_t(item.node)];
      if (n.mesh >= 0 || n.mesh < -1) {
        if (!import_mesh(n.mesh, world, item.node)) return false;
      }
      for (auto it = n.children.rbegin(); it != n.children.rend(); ++it)
        stack.push_back({*it, world, item.node});
    }
    return true;
  }

  bool import_mesh(int mi, const glm::dmat4& world, int ni) {
    const tinygltf::Node& node = model_.nodes[size_t(ni)];
    if (mi < 0 || size_t(mi) >= model_.meshes.size()) {
      return fail(label("node", ni, node.name) + " refers to mesh " + std::to_string(mi) +
                  ", but the file has " + std::to_string(model_.meshes.size()) + " meshes");
    }
    const tinygltf::Mesh& mesh = model_.meshes[size_t(mi)];
    for (size_t k = 0; k < mesh.primitives.size(); ++k) {
      const std::string name = label("mesh", mi, mesh.name) + " primitive " + std::to_string(k) + " (" +
                               label("node", ni, node.name) + ")";
      if (!import_primitive(mesh.primitives[k], name, world)) return false;
    }
    return true;
  }

  bool import_primitive(const tinygltf::Primitive& p, const std::string& name, const glm::dmat4& world) {
    // glTF 2.0 §3.7.2.1: mode 4 (triangles) is the default; 5 and 6 are strips and fans.
    const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    if (mode >= TINYGLTF_MODE_POINTS && mode <= TINYGLTF_MODE_LINE_STRIP) {
      warn("primitives of points or lines are not rendered; skipped");
      return true;
    }
    if (mode > TINYGLTF_MODE_TRIANGLE_FAN)
      return fail(name + ": mode " + std::to_string(mode) + " is not a glTF topology");
    if (p.material < -1 || (p.material >= 0 && size_t(p.material) >= model_.materials.size())) {
      return fail(name + ": material " + std::to_string(p.material) + " does not exist (the file has " +
                  std::to_string(model_.materials.size()) + " materials)");
    }
    auto attr = [&](const char* key) {
      auto it = p.attributes.find(key);
      return it == p.attributes.end() ? std::numeric_limits<int>::min() : it->second;
    };
    const int pos_a = attr("POSITION"), nrm_a = attr("NORMAL"), uv_a = attr("TEXCOORD_0"),
              uv2_a = attr("TEXCOORD_1"), tan_a = attr("TANGENT");
    constexpr int kNone = std::numeric_limits<int>::min();
    if (pos_a == kNone) {
      warn(name + ": no POSITION attribute; skipped");
      return true;
    }
    // Once per file: these are common and say the same for every primitive.
    if (!p.targets.empty()) warn("morph targets are ignored (the base shapes are used)");
    if (attr("COLOR_0") != kNone) warn("vertex colours (COLOR_0) are ignored");

    Accessor pos, nrm, uv, uv2, tan;
    if (!open_accessor(pos_a, TINYGLTF_TYPE_VEC3, "POSITION of " + name, &pos)) return false;
    const size_t nv = size_t(pos.count);
    auto open_attribute = [&](int a, int type, const char* key, Accessor* r) {
      if (a == kNone) return true;
      if (!open_accessor(a, type, std::string(key) + " of " + name, r)) return false;
      if (r->count != pos.count) {
        return fail(r->name + ": " + std::to_string(r->count) + " elements, but POSITION has " +
                    std::to_string(nv) + " (all attributes must have the same count)");
      }
      return true;
    };
    if (!open_attribute(nrm_a, TINYGLTF_TYPE_VEC3, "NORMAL", &nrm) ||
        !open_attribute(uv_a, TINYGLTF_TYPE_VEC2, "TEXCOORD_0", &uv) ||
        !open_attribute(uv2_a, TINYGLTF_TYPE_VEC2, "TEXCOORD_1", &uv2) ||
        !open_attribute(tan_a, TINYGLTF_TYPE_VEC4, "TANGENT", &tan)) {
      return false;
    }

    std::vector<uint32_t> idx;
    if (p.indices >= 0) {
      if (!read_indices(p.indices, nv, "indices of " + name, &idx)) return false;
    } else {
      idx.resize(nv);
      for (size_t i = 0; i < nv; ++i) idx[i] = uint32_t(i);
    }

    // Triangles from the topology (glTF 2.0 §3.7.2.1, "Topology types").
    std::vector<glm::uvec3> tris;
    const size_t ni = idx.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      if (ni % 3 != 0) {
        warn(name + ": " + std::to_string(ni) + " indices are not a multiple of 3; the last " +
             std::to_string(ni % 3) + " ignored");
      }
      tris.reserve(ni / 3);
      for (size_t i = 0; i + 2 < ni; i += 3) tris.emplace_back(idx[i], idx[i + 1], idx[i + 2]);
    } else if (ni >= 3) {
      tris.reserve(ni - 2);
      for (size_t i = 0; i + 2 < ni; ++i) {
        if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
          // p_i = {v_i, v_(i + 1 + i%2), v_(i + 2 - i%2)}: every other triangle swapped so all
          // keep the strip's winding.
          tris.emplace_back(idx[i], idx[i + 1 + i % 2], idx[i + 2 - i % 2]);
        } else {
          tris.emplace_back(idx[i + 1], idx[i + 2], idx[0]);  // fan: p_i = {v_(i+1), v_(i+2), v_0}
        }
      }
    }
    if (tris.empty()) {
      warn(name + ": no triangles; skipped");
      return true;
    }

    // glTF 2.0 §3.5.3: a transform that scales an axis to zero may be used to hide a node.
    if (is_singular(world)) {
      warn(name + ": its node transform is singular (a zero scale?); skipped");
      return true;
    }

    // Only the vertices the triangles use, numbered in order of first use: primitives that
    // share one large vertex accessor then neither decode nor copy all of it. A dense table
    // when the primitive uses a fair share of the accessor, a hash map otherwise.
    std::vector<uint32_t> order;
    {
      constexpr uint32_t kUnset = std::numeric_limits<uint32_t>::max();
      const bool dense = nv <= 8 * ni + 1024;
      std::vector<uint32_t> table(dense ? nv : 0, kUnset);
      std::unordered_map<uint32_t, uint32_t> sparse_table;
      for (glm::uvec3& t : tris) {
        for (int c = 0; c < 3; ++c) {
          uint32_t* r;
          if (dense) {
            r = &table[t[c]];
          } else {
            r = &sparse_table.emplace(t[c], kUnset).first->second;
          }
          if (*r == kUnset) {
            *r = uint32_t(order.size());
            order.push_back(t[c]);
          }
          t[c] = *r;
        }
      }
    }

    const glm::dmat3 linear(world);
    const glm::dmat3 normal_matrix = glm::transpose(glm::inverse(linear));
    const bool mirrored = glm::determinant(linear) < 0.0;
    GltfPrimitive prim;
    prim.name = name;
    prim.material = p.material;
    DMesh& m = prim.mesh;
    double e[4];
    m.positions.reserve(order.size());
    for (uint32_t v : order) {
      if (!element(pos, v, e)) return false;
      const glm::dvec3 q = glm::dvec3(world * glm::dvec4(e[0], e[1], e[2], 1.0));
      if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) {
        return fail(name + ": a position is not finite after the node transforms");
      }
      m.positions.push_back(q);
    }
    if (nrm_a != kNone) {
      m.normals.reserve(order.size());
      for (uint32_t v : order) {
        if (!element(nrm, v, e)) return false;
        if (e[0] == 0.0 && e[1] == 0.0 && e[2] == 0.0) {
          warn(name + ": a NORMAL has zero length; the primitive's normals are dropped");
          m.normals.clear();
          break;
        }
        glm::dvec3 q = normal_matrix * glm::dvec3(e[0], e[1], e[2]);
        const double len = glm::length(q);
        if (!(len > 0.0) || !std::isfinite(len)) {
          return fail(name + ": a normal is not finite after the node transforms");
        }
        m.normals.push_back(q / len);
      }
    }
    if (uv_a != kNone) {
      // glTF's UV origin is the image's top left, v down (§3.8.4.3); TextureDesc has row 0 at
      // V = 1, so v is flipped.
      m.uvs.reserve(order.size());
      for (uint32_t v : order) {
        if (!element(uv, v, e)) return false;
        m.uvs.emplace_back(e[0], 1.0 - e[1]);
      }
    }
    if (uv2_a != kNone) {  // the second UV set, flipped the same way
      m.uvs2.reserve(order.size());
      for (uint32_t v : order) {
        if (!element(uv2, v, e)) return false;
        m.uvs2.emplace_back(e[0], 1.0 - e[1]);
      }
    }
    // glTF 2.0 §3.7.2.1: without normals, tangents MUST be ignored.
    if (tan_a != kNone && !m.normals.empty()) {
      // Tangents transform by M itself (finalize_mesh explains why), then one Gram-Schmidt
      // step against the transformed normal. glTF's bitangent is cross(N, T) * w (§3.7.2.1)
      // and its tangent space has +Y up in the image, i.e. along decreasing glTF v, which is
      // increasing archwave v: so w keeps its meaning, sign((n x t) . dP/dv), as it is.
      m.tangents.reserve(order.size());
      for (size_t i = 0; i < order.size(); ++i) {
        if (!element(tan, order[i], e)) return false;
        glm::dvec3 t = linear * glm::dvec3(e[0], e[1], e[2]);
        t -= m.normals[i] * glm::dot(m.normals[i], t);
        const double len = glm::length(t);
        if (len > 0.0) t /= len;
        if (!std::isfinite(t.x) || !std::isfinite(t.y) || !std::isfinite(t.z)) {
          return fail(name + ": a tangent is not finite after the node transforms");
        }
        double w = e[3] < 0.0 ? -1.0 : 1.0;
        if (mirrored) w = -w;
        m.tangents.emplace_back(t, w);
      }
    }
    m.indices = std::move(tris);
    if (mirrored) {
      // A mirroring transform reverses the winding; swap two corners so the geometric normal
      // keeps agreeing with the shading normals (as finalize_mesh does).
      for (glm::uvec3& t : m.indices) std::swap(t.y, t.z);
    }
    if (prim.material >= 0 && m.uvs.empty() && !out_->bindings[size_t(prim.material)].empty()) {
      warn(name + ": its material is textured but it has no TEXCOORD_0");
    }
    out_->primitives.push_back(std::move(prim));
    return true;
  }

  std::string path_, file_name_;
  GltfImport* out_;
  std::string* error_;
  std::vector<std::string>* warnings_;
  std::set<std::string> warned_;
  FsContext fs_ctx_;
  tinygltf::Model model_;
  std::map<TextureKey, uint32_t> texture_ids_;
  std::map<std::pair<int, bool>, size_t> decoded_;  // (image, sRGB) -> index into out_->textures
  std::map<int, int> variants_;                     // glTF texture -> TextureDescs made from it
};

}  // namespace

bool load_gltf(const std::string& resolved_path, GltfImport* out, std::string* error,
               std::vector<std::string>* warnings) {
  *out = GltfImport();
  std::vector<std::string> local_warnings;
  std::vector<std::string>* w = warnings ? warnings : &local_warnings;
  try {
    Importer importer(resolved_path, out, error, w);
    if (importer.run()) return true;
  } catch (const std::bad_alloc&) {
    *error = "out of memory while reading the file";
  } catch (const std::exception& e) {
    // tinygltf indexes with .at() in places (an empty GLB buffer, ...) and nlohmann/json
    // throws on some inputs: a malformed file, reported, never a crash.
    *error = std::string("malformed glTF: ") + clean_message(e.what());
  }
  *out = GltfImport();
  return false;
}

}  // namespace scene_detail
}  // namespace aw
