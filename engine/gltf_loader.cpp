#include "engine/gltf_loader.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <numeric>
#include <optional>
#include <vector>

#include "engine/file_access.h"
#include "engine/image_io.h"
#include "engine/texture.h"

namespace penumbra::engine {
namespace {

namespace fs = std::filesystem;

// Required extensions this loader implements (KHR_mesh_quantization: integer vertex attributes,
// which the accessor reader below handles for every attribute).
const char* const kSupportedRequiredExtensions[] = {"KHR_mesh_quantization", "KHR_lights_punctual"};

std::string str(size_t v) { return std::to_string(v); }
std::string str(int v) { return std::to_string(v); }

// tinygltf's messages span lines and end in periods; ours are one line.
std::string condense(const std::string& text) {
  std::string out;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string part = text.substr(start, end - start);
    while (!part.empty() && (part.back() == '.' || part.back() == ' ' || part.back() == '\r')) part.pop_back();
    while (!part.empty() && part.front() == ' ') part.erase(part.begin());
    if (!part.empty()) out += (out.empty() ? "" : "; ") + part;
    start = end + 1;
  }
  return out.empty() ? "unknown error" : out;
}

// tinygltf calls this for every image it reads. Images given by a URI (data URI or external file)
// have their encoded bytes captured here; images in a buffer view are left for the loader, which
// checks the view's range first (tinygltf hands over the view without checking it against its
// buffer). Nothing is decoded here: only images that a loaded material uses are decoded.
struct EncodedImages {
  std::vector<std::vector<unsigned char>> bytes;  // by image index; empty: none captured
};

bool captureImage(tinygltf::Image* image, const int index, std::string*, std::string*, int, int,
                  const unsigned char* bytes, int size, void* user) {
  if (image->bufferView >= 0 || index < 0 || bytes == nullptr || size <= 0) return true;
  auto& store = static_cast<EncodedImages*>(user)->bytes;
  if (store.size() <= static_cast<size_t>(index)) store.resize(static_cast<size_t>(index) + 1);
  store[static_cast<size_t>(index)].assign(bytes, bytes + size);
  return true;
}

// glTF 2.0 (3.7.2.1): without normals, clients must compute flat normals. Vertices are unshared so
// that every triangle gets its own face normal.
void flatShade(Mesh& mesh) {
  Mesh flat;
  flat.name = mesh.name;
  flat.material = mesh.material;
  const bool uv = !mesh.texcoords.empty();
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const glm::vec3 a = mesh.positions[mesh.indices[t]], b = mesh.positions[mesh.indices[t + 1]],
                    c = mesh.positions[mesh.indices[t + 2]];
    glm::vec3 nrm = glm::cross(b - a, c - a);
    const float len = glm::length(nrm);
    nrm = len > 0.0f && std::isfinite(len) ? nrm / len : glm::vec3(0.0f, 0.0f, 1.0f);
    for (int k = 0; k < 3; ++k) {
      const uint32_t i = mesh.indices[t + static_cast<size_t>(k)];
      flat.indices.push_back(static_cast<uint32_t>(flat.positions.size()));
      flat.positions.push_back(mesh.positions[i]);
      flat.normals.push_back(nrm);
      if (uv) flat.texcoords.push_back(mesh.texcoords[i]);
    }
  }
  mesh = std::move(flat);
}

// The files tinygltf may open (buffers and images named by URI), found and checked by the loader
// before tinygltf runs (Loader::scanReferences): by the path tinygltf asks for (its JoinPath of the
// model's folder and the decoded URI), the file it resolves to inside the folder and the size it
// must have. tinygltf's own callbacks would fopen() any path (a FIFO blocks forever) and would
// also look for a URI in the current folder; these open nothing else.
struct AllowedFile {
  fs::path resolved;
  uint64_t size = 0;  // buffers: exactly this; images: at most kMaxImageFileBytes
  bool exact = false;
};
struct FileGate {
  std::map<std::string, AllowedFile> files;
};

// An encoded texture file larger than this is refused unread (a decoded texture is at most
// kMaxImagePixels RGBA8 texels, 256 MiB).
constexpr uint64_t kMaxImageFileBytes = uint64_t{256} << 20;

bool gateExists(const std::string& path, void* user) { return static_cast<FileGate*>(user)->files.count(path) > 0; }

bool gateRead(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  const auto& files = static_cast<FileGate*>(user)->files;
  const auto it = files.find(path);
  if (it == files.end()) {
    if (err) *err += "not a file the model names: " + path;
    return false;
  }
  const AllowedFile& f = it->second;
  std::error_code ec;
  const uintmax_t size = fs::is_regular_file(f.resolved, ec) ? fs::file_size(f.resolved, ec) : 0;
  if (ec || (f.exact ? size != f.size : size > kMaxImageFileBytes)) {
    if (err) *err += "changed while loading: " + path;
    return false;
  }
  std::ifstream in(f.resolved, std::ios::binary);
  out->resize(static_cast<size_t>(size));
  if (!in || (size > 0 && !in.read(reinterpret_cast<char*>(out->data()), static_cast<std::streamsize>(size)))) {
    if (err) *err += "cannot read: " + path;
    return false;
  }
  return true;
}

// tinygltf's decoding of a URI into a path (its dlib::urldecode: %XX, and '+' as a space).
std::string decodeUri(const std::string& uri) {
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return 0;
  };
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {
      out += ' ';
    } else if (uri[i] == '%' && uri.size() > i + 2) {
      out += static_cast<char>((hex(uri[i + 1]) << 4) | hex(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

std::string joinPath(const std::string& a, const std::string& b) {  // tinygltf's JoinPath
  if (a.empty()) return b;
  return a.back() == '/' ? a + b : a + "/" + b;
}

// SAX handler that only tracks nesting depth and stops past kMax levels.
struct DepthLimit : nlohmann::json_sax<nlohmann::json> {
  static constexpr int kMax = 256;
  int depth = 0;
  bool tooDeep = false;
  bool push() {
    tooDeep = ++depth > kMax;
    return !tooDeep;
  }
  bool null() override { return true; }
  bool boolean(bool) override { return true; }
  bool number_integer(number_integer_t) override { return true; }
  bool number_unsigned(number_unsigned_t) override { return true; }
  bool number_float(number_float_t, const string_t&) override { return true; }
  bool string(string_t&) override { return true; }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override { return push(); }
  bool key(string_t&) override { return true; }
  bool end_object() override {
    --depth;
    return true;
  }
  bool start_array(std::size_t) override { return push(); }
  bool end_array() override {
    --depth;
    return true;
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override { return false; }
};

int componentCount(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

// Component types glTF 2.0 allows in accessors (INT and DOUBLE are not among them).
int componentBytes(int componentType) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

template <class T>
T load(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));  // accessors need not be aligned in a malformed file
  return v;
}

// One component as float; normalized integers map to [0, 1] or [-1, 1] (glTF 2.0, 3.11).
float readComponent(const unsigned char* p, int componentType, bool normalized) {
  switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return load<float>(p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const float v = static_cast<float>(load<uint8_t>(p));
      return normalized ? v / 255.0f : v;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const float v = static_cast<float>(load<int8_t>(p));
      return normalized ? std::max(v / 127.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const float v = static_cast<float>(load<uint16_t>(p));
      return normalized ? v / 65535.0f : v;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const float v = static_cast<float>(load<int16_t>(p));
      return normalized ? std::max(v / 32767.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      const auto v = load<uint32_t>(p);
      return normalized ? static_cast<float>(static_cast<double>(v) / 4294967295.0) : static_cast<float>(v);
    }
    default: return 0.0f;
  }
}

// A checked accessor: element i's components start at base + i * stride.
struct AccessorView {
  const unsigned char* base = nullptr;  // null: no buffer view, all elements zero (glTF 2.0, 5.1.1)
  size_t stride = 0;
  size_t count = 0;
  int componentType = 0;
  int components = 0;
  bool normalized = false;
};

class Loader {
 public:
  Loader(std::string path, const LoadOptions& options, GltfLoadStats& stats)
      : path_(std::move(path)), options_(options), stats_(stats) {}

  Result<Scene> run() {
    std::vector<unsigned char> data;
    if (Status s = readFile(data); !s) return s.error();
    return run(std::move(data));
  }

  Result<Scene> run(std::vector<unsigned char> data) {
    if (data.size() > std::numeric_limits<unsigned int>::max()) return fail("file is larger than 4 GiB");
    const bool binary = data.size() >= 4 && std::memcmp(data.data(), "glTF", 4) == 0;
    if (Status s = checkJsonDepth(data, binary); !s) return s.error();
    if (Status s = scanReferences(data, binary); !s) return s.error();
    if (Status s = parse(data, binary); !s) return s.error();
    if (Status s = checkModel(); !s) return s.error();
    if (Status s = walkScene(); !s) return s.error();
    scene_.name = fs::path(path_).stem().string();
    std::error_code ec;
    scene_.sourceFiles.push_back(fs::weakly_canonical(path_, ec).string());
    scene_.sourceFiles.insert(scene_.sourceFiles.end(), sources_.begin(), sources_.end());
    if (Status s = validateScene(scene_, path_); !s) return s.error();
    return std::move(scene_);
  }

 private:
  Error fail(const std::string& what) const { return Error{path_, what}; }

  Status readFile(std::vector<unsigned char>& data) {
    std::error_code ec;
    if (!fs::is_regular_file(path_, ec)) return fail("cannot open file");
    std::ifstream in(path_, std::ios::binary);
    if (!in) return fail("cannot open file");
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    if (size < 0) return fail("cannot read file");
    // tinygltf takes the length as unsigned int.
    if (static_cast<unsigned long long>(size) > std::numeric_limits<unsigned int>::max())
      return fail("file is larger than 4 GiB");
    if (options_.maxBytes > 0 && static_cast<uint64_t>(size) > options_.maxBytes)
      return fail("file of " + std::to_string(size) + " bytes is larger than the memory limit of " +
                  std::to_string(options_.maxBytes) + " bytes");
    bytesRead_ = static_cast<uint64_t>(size);
    in.seekg(0, std::ios::beg);
    data.resize(static_cast<size_t>(size));
    if (size > 0 && !in.read(reinterpret_cast<char*>(data.data()), size)) return fail("cannot read file");
    return Ok{};
  }

  Status parse(const std::vector<unsigned char>& data, bool binary) {
    tinygltf::TinyGLTF gltf;
    gltf.SetImageLoader(&captureImage, &encoded_);
    gltf.SetFsCallbacks(
        tinygltf::FsCallbacks{&gateExists, &tinygltf::ExpandFilePath, &gateRead, &tinygltf::WriteWholeFile, &gate_});
    std::string err, warn;
    const std::string baseDir = fs::path(path_).parent_path().string();
    bool ok = false;
    try {
      const auto length = static_cast<unsigned int>(data.size());
      if (binary)
        ok = gltf.LoadBinaryFromMemory(&model_, &err, &warn, data.data(), length, baseDir);
      else
        ok = gltf.LoadASCIIFromString(&model_, &err, &warn, reinterpret_cast<const char*>(data.data()), length, baseDir);
    } catch (const std::exception& e) {
      return fail("invalid glTF: " + condense(e.what()));
    }
    if (ok) return Ok{};
    if (binary) return fail("invalid glTF binary: " + condense(err));
    return explainTextFailure(data, err);
  }

  // The JSON text of the model (a .glb's JSON chunk), or nothing when the container is malformed
  // (tinygltf then says what is wrong).
  static std::optional<std::pair<size_t, size_t>> jsonRange(const std::vector<unsigned char>& data, bool binary) {
    if (!binary) return std::pair<size_t, size_t>{0, data.size()};
    auto u32 = [&](size_t at) {
      uint32_t v = 0;
      std::memcpy(&v, data.data() + at, 4);
      return v;
    };
    if (data.size() < 20 || u32(16) != 0x4E4F534Au) return std::nullopt;  // "JSON" chunk
    const size_t chunk = u32(12);
    if (chunk > data.size() - 20) return std::nullopt;
    return std::pair<size_t, size_t>{20, chunk};
  }

  // Before tinygltf reads anything: every file the model names by URI is resolved inside the
  // model's folder (file_access.h) and its size checked (a buffer's file must hold exactly its
  // byteLength); only those files are open to tinygltf (FileGate). A buffer no buffer view of an
  // accessor or an image uses is not read at all: its URI is replaced by a one-byte data URI in
  // the text tinygltf parses.
  Status scanReferences(std::vector<unsigned char>& data, bool binary) {
    const std::optional<std::pair<size_t, size_t>> range = jsonRange(data, binary);
    if (!range) return Ok{};
    nlohmann::json doc;
    try {
      doc = nlohmann::json::parse(data.begin() + static_cast<std::ptrdiff_t>(range->first),
                                  data.begin() + static_cast<std::ptrdiff_t>(range->first + range->second));
    } catch (const std::exception&) {
      return Ok{};  // tinygltf reports the JSON error
    }
    if (!doc.is_object()) return Ok{};
    const std::string baseDir = fs::path(path_).parent_path().string();
    auto array = [&](const char* key) -> nlohmann::json* {
      auto it = doc.find(key);
      return it != doc.end() && it->is_array() ? &*it : nullptr;
    };
    // Buffers used: through a buffer view of an accessor or an image.
    std::vector<char> usedView, usedBuffer;
    if (nlohmann::json* views = array("bufferViews")) usedView.assign(views->size(), 0);
    for (const char* owner : {"accessors", "images"})
      if (nlohmann::json* list = array(owner))
        for (const nlohmann::json& e : *list)
          if (e.is_object() && e.contains("bufferView") && e["bufferView"].is_number_unsigned() &&
              e["bufferView"].get<uint64_t>() < usedView.size())
            usedView[e["bufferView"].get<size_t>()] = 1;
    if (nlohmann::json* buffers = array("buffers")) usedBuffer.assign(buffers->size(), 0);
    if (nlohmann::json* views = array("bufferViews"))
      for (size_t v = 0; v < views->size(); ++v) {
        const nlohmann::json& bv = (*views)[v];
        if (usedView[v] && bv.is_object() && bv.contains("buffer") && bv["buffer"].is_number_unsigned() &&
            bv["buffer"].get<uint64_t>() < usedBuffer.size())
          usedBuffer[bv["buffer"].get<size_t>()] = 1;
      }
    bool rewrite = false;
    if (nlohmann::json* buffers = array("buffers"))
      for (size_t i = 0; i < buffers->size(); ++i) {
        nlohmann::json& b = (*buffers)[i];
        if (!b.is_object() || !b.contains("uri") || !b["uri"].is_string()) continue;
        const std::string uri = b["uri"].get<std::string>();
        const std::string what = "buffer " + str(i) + " ('" + uri + "')";
        const std::string scheme = uriScheme(uri);
        if (scheme == "data") continue;
        if (!scheme.empty()) return fail(what + ": URI scheme '" + scheme + "' is not supported (relative paths and data: only)");
        if (!usedBuffer[i]) {  // never read: tinygltf gets one zero byte instead
          b["uri"] = "data:application/octet-stream;base64,AA==";
          b["byteLength"] = 1;
          ++stats_.buffersSkipped;
          rewrite = true;
          continue;
        }
        Result<fs::path> file = resolveReference(baseDir, decodeUri(uri), options_, path_, what);
        if (!file) return file.error();
        std::error_code ec;
        const uintmax_t size = fs::file_size(*file, ec);
        if (!b.contains("byteLength") || !b["byteLength"].is_number_unsigned())
          return fail(what + " has no valid byteLength");
        const uint64_t want = b["byteLength"].get<uint64_t>();
        if (ec || size != want)
          return fail(what + ": the file holds " + std::to_string(size) + " bytes, the buffer's byteLength is " +
                      std::to_string(want));
        bytesRead_ += want;
        if (options_.maxBytes > 0 && bytesRead_ > options_.maxBytes)
          return fail(what + ": the model's files hold more than the memory limit of " + std::to_string(options_.maxBytes) +
                      " bytes");
        gate_.files[joinPath(baseDir, decodeUri(uri))] = {*file, want, true};
        sources_.push_back(file->string());
      }
    if (nlohmann::json* images = array("images"))
      for (size_t i = 0; i < images->size(); ++i) {
        const nlohmann::json& im = (*images)[i];
        if (!im.is_object() || !im.contains("uri") || !im["uri"].is_string()) continue;
        const std::string uri = im["uri"].get<std::string>();
        const std::string what = "image " + str(i) + " ('" + uri + "')";
        const std::string scheme = uriScheme(uri);
        if (scheme == "data") continue;
        if (!scheme.empty()) return fail(what + ": URI scheme '" + scheme + "' is not supported (relative paths and data: only)");
        Result<fs::path> file = resolveReference(baseDir, decodeUri(uri), options_, path_, what);
        if (!file) {
          imageProblems_.emplace(i, file.error().what);  // an error only if a material uses it (texture())
          continue;
        }
        std::error_code ec;
        const uintmax_t size = fs::file_size(*file, ec);
        if (ec || size > kMaxImageFileBytes) {
          imageProblems_.emplace(i, what + " is larger than " + std::to_string(kMaxImageFileBytes >> 20) + " MiB");
          continue;
        }
        gate_.files[joinPath(baseDir, decodeUri(uri))] = {*file, size, false};
        sources_.push_back(file->string());
      }
    if (!rewrite) return Ok{};
    const std::string text = doc.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
    if (!binary) {
      data.assign(text.begin(), text.end());
      return Ok{};
    }
    // The .glb again: header, the new JSON chunk (padded with spaces to 4 bytes), the rest as it was.
    const size_t oldEnd = 20 + ((range->second + 3) & ~size_t{3});
    std::vector<unsigned char> glb(data.begin(), data.begin() + 12);
    const size_t padded = (text.size() + 3) & ~size_t{3};
    auto put32 = [&](uint32_t v) {
      for (int k = 0; k < 4; ++k) glb.push_back(static_cast<unsigned char>(v >> (8 * k)));
    };
    put32(static_cast<uint32_t>(padded));
    put32(0x4E4F534Au);
    glb.insert(glb.end(), text.begin(), text.end());
    glb.resize(20 + padded, ' ');
    if (oldEnd < data.size()) glb.insert(glb.end(), data.begin() + static_cast<std::ptrdiff_t>(oldEnd), data.end());
    const auto total = static_cast<uint32_t>(glb.size());
    std::memcpy(glb.data() + 8, &total, 4);
    data = std::move(glb);
    return Ok{};
  }

  // tinygltf converts "extras" and "extensions" with a recursive function and no depth limit, so
  // deeply nested JSON would overflow the stack. nlohmann's SAX parser is iterative: measure the
  // depth with it first (in a .glb, of the JSON chunk; a malformed container is left to tinygltf).
  Status checkJsonDepth(const std::vector<unsigned char>& data, bool binary) const {
    const unsigned char* begin = data.data();
    size_t size = data.size();
    if (binary) {
      auto u32 = [&](size_t at) {
        uint32_t v = 0;
        std::memcpy(&v, data.data() + at, 4);
        return v;
      };
      if (size < 20 || u32(16) != 0x4E4F534Au) return Ok{};  // "JSON" chunk
      const size_t chunk = u32(12);
      if (chunk > size - 20) return Ok{};
      begin += 20;
      size = chunk;
    }
    DepthLimit limit;
    try {
      nlohmann::json::sax_parse(begin, begin + size, &limit);
    } catch (const std::exception&) {
      return Ok{};  // not JSON: tinygltf says so
    }
    if (limit.tooDeep) return fail("JSON nested deeper than " + str(DepthLimit::kMax) + " levels");
    return Ok{};
  }

  // Says whether the text is no glTF at all (not JSON, or JSON without an asset) or a broken one.
  Status explainTextFailure(const std::vector<unsigned char>& data, const std::string& err) const {
    const auto* begin = reinterpret_cast<const char*>(data.data());
    try {
      const nlohmann::json j = nlohmann::json::parse(begin, begin + data.size());
      if (!j.is_object() || !j.contains("asset")) return fail("not a glTF file (no \"asset\" object)");
    } catch (const nlohmann::json::parse_error& e) {
      size_t line = 1, column = 1;
      for (size_t i = 0; i + 1 < e.byte && i < data.size(); ++i) {
        if (data[i] == '\n') {
          ++line;
          column = 1;
        } else {
          ++column;
        }
      }
      return fail("not a glTF file (invalid JSON at line " + str(line) + ", column " + str(column) + ")");
    }
    return fail("invalid glTF: " + condense(err));
  }

  Status checkModel() {
    const std::string& version = model_.asset.version;
    if (version.empty() || version[0] != '2') return fail("glTF version '" + version + "' is not supported (2.x expected)");
    for (const std::string& ext : model_.extensionsRequired) {
      const bool supported = std::any_of(std::begin(kSupportedRequiredExtensions), std::end(kSupportedRequiredExtensions),
                                         [&](const char* s) { return ext == s; });
      if (!supported) return fail("required extension " + ext + " is not supported");
    }
    // Views an accessor or an image uses (the others, and the buffers only they use, are never
    // read: scanReferences may have replaced those buffers with one byte).
    std::vector<char> used(model_.bufferViews.size(), 0);
    for (const tinygltf::Accessor& a : model_.accessors)
      if (a.bufferView >= 0 && static_cast<size_t>(a.bufferView) < used.size()) used[static_cast<size_t>(a.bufferView)] = 1;
    for (const tinygltf::Image& im : model_.images)
      if (im.bufferView >= 0 && static_cast<size_t>(im.bufferView) < used.size()) used[static_cast<size_t>(im.bufferView)] = 1;
    for (size_t i = 0; i < model_.bufferViews.size(); ++i) {
      if (!used[i]) continue;
      const tinygltf::BufferView& bv = model_.bufferViews[i];
      if (bv.buffer < 0 || static_cast<size_t>(bv.buffer) >= model_.buffers.size())
        return fail("buffer view " + str(i) + " refers to buffer " + str(bv.buffer) + ", which does not exist");
      const size_t size = model_.buffers[static_cast<size_t>(bv.buffer)].data.size();
      if (bv.byteOffset > size || bv.byteLength > size - bv.byteOffset)
        return fail("buffer view " + str(i) + " reads past the end of buffer " + str(bv.buffer));
    }
    return Ok{};
  }

  // --- Accessors ---------------------------------------------------------------------------------

  Result<AccessorView> accessor(int index) const {
    if (index < 0 || static_cast<size_t>(index) >= model_.accessors.size())
      return fail("accessor " + str(index) + " does not exist");
    const tinygltf::Accessor& a = model_.accessors[static_cast<size_t>(index)];
    const std::string name = "accessor " + str(index);
    if (a.sparse.isSparse) return fail(name + " is sparse (sparse accessors are not supported)");
    AccessorView v;
    v.components = componentCount(a.type);
    v.componentType = a.componentType;
    v.normalized = a.normalized;
    v.count = a.count;
    // 2^26 elements (64 M vertices or indices) per accessor: far beyond any scene we render, and
    // small enough that a file claiming more cannot make us allocate gigabytes.
    if (a.count > (size_t{1} << 26)) return fail(name + " has " + str(a.count) + " elements (more than 2^26)");
    const int bytes = componentBytes(a.componentType);
    if (v.components == 0) return fail(name + " has an invalid type");
    if (bytes == 0) return fail(name + " has an invalid component type " + str(a.componentType));
    const size_t elementSize = static_cast<size_t>(v.components) * static_cast<size_t>(bytes);
    if (a.bufferView < 0) return v;  // all zeros
    if (static_cast<size_t>(a.bufferView) >= model_.bufferViews.size())
      return fail(name + " refers to buffer view " + str(a.bufferView) + ", which does not exist");
    const tinygltf::BufferView& bv = model_.bufferViews[static_cast<size_t>(a.bufferView)];
    v.stride = bv.byteStride != 0 ? bv.byteStride : elementSize;
    if (v.stride < elementSize)
      return fail("buffer view " + str(a.bufferView) + " has byteStride " + str(bv.byteStride) + ", less than the " +
                  str(elementSize) + "-byte elements of " + name);
    // Elements 0 .. count - 1 must lie in the view: byteOffset + (count - 1) * stride + elementSize
    // <= byteLength, evaluated without overflow.
    if (v.count > 0) {
      const bool fits = a.byteOffset <= bv.byteLength && elementSize <= bv.byteLength - a.byteOffset &&
                        (v.count - 1) <= (bv.byteLength - a.byteOffset - elementSize) / v.stride;
      if (!fits) return fail(name + " reads past the end of buffer view " + str(a.bufferView));
    }
    // checkModel() verified that the view lies in its buffer.
    v.base = model_.buffers[static_cast<size_t>(bv.buffer)].data.data() + bv.byteOffset + a.byteOffset;
    return v;
  }

  // Reads a VECn float attribute (n = N) of any allowed component type.
  template <int N>
  Status readVectors(int index, const std::string& what, std::vector<glm::vec<N, float>>& out) const {
    Result<AccessorView> r = accessor(index);
    if (!r) return r.error();
    const AccessorView& v = *r;
    if (v.components != N || componentCount(model_.accessors[static_cast<size_t>(index)].type) != N)
      return fail(what + " accessor " + str(index) + " must be VEC" + str(N));
    out.assign(v.count, glm::vec<N, float>(0.0f));
    if (v.base == nullptr) return Ok{};
    const size_t cbytes = static_cast<size_t>(componentBytes(v.componentType));
    for (size_t i = 0; i < v.count; ++i) {
      const unsigned char* e = v.base + i * v.stride;
      for (int c = 0; c < N; ++c) out[i][c] = readComponent(e + static_cast<size_t>(c) * cbytes, v.componentType, v.normalized);
    }
    return Ok{};
  }

  Status readIndices(int index, std::vector<uint32_t>& out) const {
    Result<AccessorView> r = accessor(index);
    if (!r) return r.error();
    const AccessorView& v = *r;
    if (model_.accessors[static_cast<size_t>(index)].type != TINYGLTF_TYPE_SCALAR ||
        (v.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && v.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
         v.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
      return fail("index accessor " + str(index) + " must hold unsigned byte, short or int scalars");
    out.assign(v.count, 0u);
    if (v.base == nullptr) return Ok{};
    for (size_t i = 0; i < v.count; ++i) {
      const unsigned char* e = v.base + i * v.stride;
      switch (v.componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: out[i] = load<uint8_t>(e); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: out[i] = load<uint16_t>(e); break;
        default: out[i] = load<uint32_t>(e); break;
      }
    }
    return Ok{};
  }

  // --- Materials and textures --------------------------------------------------------------------

  Result<int> texture(int gltfTexture, const std::string& owner) {
    if (gltfTexture < 0 || static_cast<size_t>(gltfTexture) >= model_.textures.size())
      return fail(owner + " uses texture " + str(gltfTexture) + ", which does not exist");
    const int image = model_.textures[static_cast<size_t>(gltfTexture)].source;
    if (image < 0) return -1;  // the image comes through an extension: none we support
    if (static_cast<size_t>(image) >= model_.images.size())
      return fail("texture " + str(gltfTexture) + " uses image " + str(image) + ", which does not exist");
    if (auto it = textureOfImage_.find(image); it != textureOfImage_.end()) return it->second;

    if (auto p = imageProblems_.find(static_cast<size_t>(image)); p != imageProblems_.end()) return fail(p->second);
    const tinygltf::Image& img = model_.images[static_cast<size_t>(image)];
    std::string label = "image " + str(image);
    if (!img.uri.empty() && img.uri.rfind("data:", 0) != 0) label += " ('" + img.uri + "')";
    else if (!img.name.empty()) label += " ('" + img.name + "')";
    const unsigned char* bytes = nullptr;
    size_t size = 0;
    if (img.bufferView >= 0) {
      if (static_cast<size_t>(img.bufferView) >= model_.bufferViews.size())
        return fail(label + " refers to buffer view " + str(img.bufferView) + ", which does not exist");
      const tinygltf::BufferView& bv = model_.bufferViews[static_cast<size_t>(img.bufferView)];
      bytes = model_.buffers[static_cast<size_t>(bv.buffer)].data.data() + bv.byteOffset;  // range checked
      size = bv.byteLength;
    } else if (static_cast<size_t>(image) < encoded_.bytes.size()) {
      bytes = encoded_.bytes[static_cast<size_t>(image)].data();
      size = encoded_.bytes[static_cast<size_t>(image)].size();
    }
    if (size == 0) return fail(label + " cannot be read (missing or empty file)");
    Result<raster::ImageRgba8> decoded = decodeTexture(bytes, size, img.mimeType, label);
    if (!decoded) return fail(label + ": " + decoded.error().what);
    Texture t;
    t.name = !img.name.empty() ? img.name : !img.uri.empty() && img.uri.rfind("data:", 0) != 0 ? img.uri : label;
    t.mips.push_back(std::move(*decoded));
    buildMips(t);
    scene_.textures.push_back(std::move(t));
    const int ours = static_cast<int>(scene_.textures.size()) - 1;
    textureOfImage_[image] = ours;
    return ours;
  }

  Result<int> material(int gltfMaterial) {
    if (auto it = materialMap_.find(gltfMaterial); it != materialMap_.end()) return it->second;
    const tinygltf::Material& m = model_.materials[static_cast<size_t>(gltfMaterial)];
    const std::string owner = "material " + str(gltfMaterial);
    Material out;
    out.name = m.name.empty() ? owner : m.name;
    const std::vector<double>& f = m.pbrMetallicRoughness.baseColorFactor;
    if (f.size() == 4)
      out.baseColorFactor = glm::vec4(static_cast<float>(f[0]), static_cast<float>(f[1]), static_cast<float>(f[2]),
                                      static_cast<float>(f[3]));
    else if (!f.empty())
      return fail(owner + ": baseColorFactor must have 4 numbers");
    for (int c = 0; c < 4; ++c)
      if (!std::isfinite(out.baseColorFactor[c])) return fail(owner + ": baseColorFactor is not finite");
    if (m.pbrMetallicRoughness.baseColorTexture.index >= 0) {
      Result<int> t = texture(m.pbrMetallicRoughness.baseColorTexture.index, owner);
      if (!t) return t.error();
      out.baseColorTexture = *t;
    }
    scene_.materials.push_back(std::move(out));
    const int ours = static_cast<int>(scene_.materials.size()) - 1;
    materialMap_[gltfMaterial] = ours;
    return ours;
  }

  // --- Meshes ------------------------------------------------------------------------------------

  // Triangle list from the primitive's vertex order (glTF 2.0, 3.7.2.1: strips alternate winding;
  // fans pivot on the first vertex, triangle i being (i + 1, i + 2, 0)).
  static std::vector<uint32_t> triangleList(const std::vector<uint32_t>& order, int mode) {
    if (mode == TINYGLTF_MODE_TRIANGLES) return order;
    std::vector<uint32_t> tris;
    if (order.size() < 3) return tris;
    tris.reserve((order.size() - 2) * 3);
    for (size_t i = 0; i + 2 < order.size(); ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        const bool odd = (i & 1) != 0;
        tris.insert(tris.end(), {order[i], order[odd ? i + 2 : i + 1], order[odd ? i + 1 : i + 2]});
      } else {
        tris.insert(tris.end(), {order[i + 1], order[i + 2], order[0]});
      }
    }
    return tris;
  }

  Status primitive(int meshIndex, size_t primIndex, std::vector<int>& out) {
    const tinygltf::Mesh& gm = model_.meshes[static_cast<size_t>(meshIndex)];
    const tinygltf::Primitive& p = gm.primitives[primIndex];
    const std::string owner = "mesh " + str(meshIndex) + " primitive " + str(primIndex);
    const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
    if (mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP ||
        mode == TINYGLTF_MODE_LINE_STRIP) {
      ++stats_.skippedPrimitives;
      return Ok{};
    }
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN)
      return fail(owner + ": invalid mode " + str(mode));

    Mesh mesh;
    mesh.name = (gm.name.empty() ? "mesh " + str(meshIndex) : gm.name) +
                (gm.primitives.size() > 1 ? "/" + str(primIndex) : std::string());
    int texcoordSet = 0;
    if (p.material >= 0) {
      if (static_cast<size_t>(p.material) >= model_.materials.size())
        return fail(owner + " uses material " + str(p.material) + ", which does not exist");
      Result<int> m = material(p.material);
      if (!m) return m.error();
      mesh.material = *m;
      const tinygltf::TextureInfo& bct = model_.materials[static_cast<size_t>(p.material)].pbrMetallicRoughness.baseColorTexture;
      if (bct.index >= 0) texcoordSet = std::max(bct.texCoord, 0);
    }

    const auto pos = p.attributes.find("POSITION");
    if (pos == p.attributes.end()) return fail(owner + " has no POSITION attribute");
    if (Status s = readVectors<3>(pos->second, owner + " POSITION", mesh.positions); !s) return s;
    const size_t n = mesh.positions.size();
    if (const auto it = p.attributes.find("NORMAL"); it != p.attributes.end()) {
      if (Status s = readVectors<3>(it->second, owner + " NORMAL", mesh.normals); !s) return s;
      if (mesh.normals.size() != n) return fail(owner + ": NORMAL count differs from POSITION count");
      // Normals that cannot be used make the whole set recomputed (validateScene does it).
      for (glm::vec3& nrm : mesh.normals) {
        const float len = glm::length(nrm);
        if (!(len > 0.0f) || !std::isfinite(len)) {
          mesh.normals.clear();
          break;
        }
        nrm /= len;
      }
    }
    if (const auto it = p.attributes.find("TEXCOORD_" + str(texcoordSet)); it != p.attributes.end()) {
      if (Status s = readVectors<2>(it->second, owner + " TEXCOORD_" + str(texcoordSet), mesh.texcoords); !s) return s;
      if (mesh.texcoords.size() != n) return fail(owner + ": TEXCOORD_" + str(texcoordSet) + " count differs from POSITION count");
    }

    std::vector<uint32_t> order;
    if (p.indices >= 0) {
      if (Status s = readIndices(p.indices, order); !s) return s;
    } else {
      if (n > std::numeric_limits<uint32_t>::max()) return fail(owner + " has too many vertices");
      order.assign(n, 0u);
      std::iota(order.begin(), order.end(), 0u);
    }
    mesh.indices = triangleList(order, mode);
    if (mesh.indices.size() % 3 != 0)
      return fail(owner + ": " + str(mesh.indices.size()) + " vertices do not make whole triangles");
    for (uint32_t i : mesh.indices)
      if (i >= n) return fail(owner + ": index " + str(static_cast<size_t>(i)) + " out of range (" + str(n) + " vertices)");
    if (mesh.normals.empty()) flatShade(mesh);
    scene_.meshes.push_back(std::move(mesh));
    out.push_back(static_cast<int>(scene_.meshes.size()) - 1);
    return Ok{};
  }

  // Our meshes for a glTF mesh, converted on first use.
  Result<const std::vector<int>*> mesh(int index) {
    if (index < 0 || static_cast<size_t>(index) >= model_.meshes.size()) return fail("mesh " + str(index) + " does not exist");
    if (auto it = meshMap_.find(index); it != meshMap_.end()) return &it->second;
    std::vector<int> ours;
    for (size_t k = 0; k < model_.meshes[static_cast<size_t>(index)].primitives.size(); ++k)
      if (Status s = primitive(index, k, ours); !s) return s.error();
    return &(meshMap_[index] = std::move(ours));
  }

  // --- Nodes -------------------------------------------------------------------------------------

  Result<glm::mat4> localTransform(size_t index) const {
    const tinygltf::Node& node = model_.nodes[index];
    const std::string owner = "node " + str(index);
    auto finite = [](const std::vector<double>& v) { return std::all_of(v.begin(), v.end(), [](double d) { return std::isfinite(d); }); };
    if (!finite(node.matrix) || !finite(node.translation) || !finite(node.rotation) || !finite(node.scale))
      return fail(owner + " has a non-finite transform");
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16) return fail(owner + ": matrix must have 16 numbers");
      glm::mat4 m;
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) m[c][r] = static_cast<float>(node.matrix[static_cast<size_t>(c * 4 + r)]);  // column-major
      return m;
    }
    glm::mat4 m(1.0f);
    if (!node.translation.empty()) {
      if (node.translation.size() != 3) return fail(owner + ": translation must have 3 numbers");
      m = glm::translate(m, glm::vec3(static_cast<float>(node.translation[0]), static_cast<float>(node.translation[1]),
                                      static_cast<float>(node.translation[2])));
    }
    if (!node.rotation.empty()) {
      if (node.rotation.size() != 4) return fail(owner + ": rotation must have 4 numbers");
      // glTF stores (x, y, z, w); glm::quat's constructor takes w first.
      glm::quat q(static_cast<float>(node.rotation[3]), static_cast<float>(node.rotation[0]),
                  static_cast<float>(node.rotation[1]), static_cast<float>(node.rotation[2]));
      const float len = glm::length(q);
      if (!(len > 0.0f)) return fail(owner + ": rotation is a zero quaternion");
      m = m * glm::mat4_cast(q / len);
    }
    if (!node.scale.empty()) {
      if (node.scale.size() != 3) return fail(owner + ": scale must have 3 numbers");
      m = glm::scale(m, glm::vec3(static_cast<float>(node.scale[0]), static_cast<float>(node.scale[1]),
                                  static_cast<float>(node.scale[2])));
    }
    return m;
  }

  Status camera(int index, size_t node, const glm::mat4& world) {
    if (index < 0 || static_cast<size_t>(index) >= model_.cameras.size())
      return fail("node " + str(node) + " uses camera " + str(index) + ", which does not exist");
    const tinygltf::Camera& c = model_.cameras[static_cast<size_t>(index)];
    if (c.type != "perspective" || scene_.camera) return Ok{};
    const glm::mat3 basis(world);
    const glm::vec3 forward = basis * glm::vec3(0.0f, 0.0f, -1.0f), up = basis * glm::vec3(0.0f, 1.0f, 0.0f);
    const float fl = glm::length(forward), ul = glm::length(up);
    if (!(fl > 0.0f) || !(ul > 0.0f) || !std::isfinite(fl) || !std::isfinite(ul))
      return fail("camera " + str(index) + " sits on node " + str(node) + ", whose transform is degenerate");
    Camera cam;
    cam.eye = glm::vec3(world[3]);
    cam.target = cam.eye + forward / fl;
    cam.up = up / ul;
    cam.fovYDegrees = static_cast<float>(c.perspective.yfov * 180.0 / std::numbers::pi);
    cam.znear = c.perspective.znear > 0.0 ? static_cast<float>(c.perspective.znear) : 0.0f;
    // zfar absent (0 in tinygltf) means an infinite projection: 0 lets the renderer fit it.
    cam.zfar = c.perspective.zfar > c.perspective.znear && std::isfinite(c.perspective.zfar)
                   ? static_cast<float>(c.perspective.zfar) : 0.0f;
    scene_.camera = cam;
    return Ok{};
  }

  // KHR_lights_punctual: the light a node names sits at the node's origin and shines down its -z.
  // glTF's photometric intensities (candela for point and spot lights, lux for directional ones)
  // become ours divided by pi: we shade albedo * (n . l) * intensity, glTF's BRDF is albedo / pi.
  Status light(const tinygltf::Node& node, size_t index, const glm::mat4& world) {
    const auto ext = node.extensions.find("KHR_lights_punctual");
    if (ext == node.extensions.end() || !ext->second.IsObject() || !ext->second.Has("light")) return Ok{};
    const tinygltf::Value& v = ext->second.Get("light");
    if (!v.IsInt() && !v.IsNumber()) return fail("node " + str(index) + ": KHR_lights_punctual light must be an index");
    const int li = v.IsInt() ? v.Get<int>() : static_cast<int>(v.GetNumberAsDouble());
    if (li < 0 || static_cast<size_t>(li) >= model_.lights.size())
      return fail("node " + str(index) + " uses light " + str(li) + ", which does not exist");
    const tinygltf::Light& l = model_.lights[static_cast<size_t>(li)];
    const std::string owner = "light " + str(li);
    glm::vec3 color(1.0f);
    if (!l.color.empty()) {
      if (l.color.size() != 3) return fail(owner + ": color must have 3 numbers");
      color = glm::vec3(static_cast<float>(l.color[0]), static_cast<float>(l.color[1]), static_cast<float>(l.color[2]));
    }
    const float intensity = static_cast<float>(l.intensity / std::numbers::pi);
    const float range = static_cast<float>(l.range);
    for (float f : {color.x, color.y, color.z, intensity, range})
      if (!std::isfinite(f) || f < 0.0f) return fail(owner + ": color, intensity and range must be finite and >= 0");
    const glm::vec3 position(world[3]);
    const glm::vec3 forward = glm::mat3(world) * glm::vec3(0.0f, 0.0f, -1.0f);
    const float len = glm::length(forward);
    if (l.type == "point") {
      scene_.pointLights.push_back({position, color, intensity, range});
      return Ok{};
    }
    if (!(len > 0.0f) || !std::isfinite(len)) return fail(owner + " sits on node " + str(index) + ", whose transform is degenerate");
    if (l.type == "directional") {
      scene_.directionalLights.push_back({forward / len, color, intensity});
    } else if (l.type == "spot") {
      SpotLight sl{position, forward / len, color, intensity, range, static_cast<float>(l.spot.innerConeAngle),
                   static_cast<float>(l.spot.outerConeAngle)};
      if (!(sl.innerCone >= 0.0f && sl.innerCone < sl.outerCone && sl.outerCone <= std::numbers::pi_v<float> / 2))
        return fail(owner + ": spot cones must satisfy 0 <= innerConeAngle < outerConeAngle <= pi/2");
      scene_.spotLights.push_back(sl);
    } else {
      return fail(owner + ": type '" + l.type + "' is not directional, point or spot");
    }
    return Ok{};
  }

  Status walkScene() {
    std::vector<int> roots;
    if (model_.defaultScene >= 0 || !model_.scenes.empty()) {
      const int s = model_.defaultScene >= 0 ? model_.defaultScene : 0;
      if (static_cast<size_t>(s) >= model_.scenes.size()) return fail("default scene " + str(s) + " does not exist");
      roots = model_.scenes[static_cast<size_t>(s)].nodes;
    } else {
      std::vector<char> isChild(model_.nodes.size(), 0);
      for (const tinygltf::Node& node : model_.nodes)
        for (int c : node.children)
          if (c >= 0 && static_cast<size_t>(c) < isChild.size()) isChild[static_cast<size_t>(c)] = 1;
      for (size_t i = 0; i < model_.nodes.size(); ++i)
        if (!isChild[i]) roots.push_back(static_cast<int>(i));
    }
    // Depth-first, pre-order, children in file order; an explicit stack, so that deep hierarchies
    // cannot overflow the call stack. A node met twice (a cycle, or a child of two parents) is an error.
    struct Item {
      int node;
      glm::mat4 parent;
    };
    std::vector<Item> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, glm::mat4(1.0f)});
    std::vector<char> visited(model_.nodes.size(), 0);
    while (!stack.empty()) {
      const Item item = stack.back();
      stack.pop_back();
      if (item.node < 0 || static_cast<size_t>(item.node) >= model_.nodes.size())
        return fail("node " + str(item.node) + " does not exist");
      const auto index = static_cast<size_t>(item.node);
      if (visited[index]) return fail("node " + str(index) + " appears twice in the node hierarchy");
      visited[index] = 1;
      Result<glm::mat4> local = localTransform(index);
      if (!local) return local.error();
      const glm::mat4 world = item.parent * *local;
      const tinygltf::Node& node = model_.nodes[index];
      if (node.mesh >= 0) {
        Result<const std::vector<int>*> ours = mesh(node.mesh);
        if (!ours) return ours.error();
        for (int m : **ours)
          scene_.instances.push_back(Instance{node.name.empty() ? "node " + str(index) : node.name, m, world});
      }
      if (node.camera >= 0)
        if (Status s = camera(node.camera, index, world); !s) return s;
      if (Status s = light(node, index, world); !s) return s;
      for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) stack.push_back({*it, world});
    }
    return Ok{};
  }

  std::string path_;
  LoadOptions options_;
  GltfLoadStats& stats_;
  FileGate gate_;
  uint64_t bytesRead_ = 0;             // the model and its buffers
  std::vector<std::string> sources_;   // files read besides the model itself
  std::map<size_t, std::string> imageProblems_;  // named images outside the folder, missing, too large
  tinygltf::Model model_;
  EncodedImages encoded_;
  Scene scene_;
  std::map<int, std::vector<int>> meshMap_;  // glTF mesh -> our meshes (one per kept primitive)
  std::map<int, int> materialMap_;           // glTF material -> ours
  std::map<int, int> textureOfImage_;        // glTF image -> our texture
};

}  // namespace

Result<Scene> loadGltf(const std::string& path, const LoadOptions& options, GltfLoadStats& stats) {
  stats = GltfLoadStats{};
  try {
    return Loader(path, options, stats).run();
  } catch (const std::bad_alloc&) {
    return Error{path, "out of memory while loading"};
  } catch (const std::exception& e) {
    return Error{path, "invalid glTF: " + condense(e.what())};
  }
}

Result<Scene> parseGltf(std::vector<unsigned char> bytes, const std::string& path, const LoadOptions& options) {
  GltfLoadStats stats;
  try {
    return Loader(path, options, stats).run(std::move(bytes));
  } catch (const std::bad_alloc&) {
    return Error{path, "out of memory while loading"};
  } catch (const std::exception& e) {
    return Error{path, "invalid glTF: " + condense(e.what())};
  }
}

Result<Scene> loadGltf(const std::string& path, const LoadOptions& options) {
  GltfLoadStats stats;
  return loadGltf(path, options, stats);
}

}  // namespace penumbra::engine
