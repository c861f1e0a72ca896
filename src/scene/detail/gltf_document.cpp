// glTF 2.0 containers (.gltf JSON, .glb binary), buffers (GLB chunk, data URI, external file) and
// accessor decoding with bounds checks against buffer views and buffers.
#include "scene/detail/gltf_document.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <utility>

#include "beamtrace/core/error.hpp"
#include "text/file_bytes.hpp"

namespace beamtrace::detail {
namespace {

using nlohmann::json;

constexpr std::uint32_t kGlbMagic = 0x46546C67;      // "glTF"
constexpr std::uint32_t kGlbChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kGlbChunkBin = 0x004E4942;   // "BIN\0"
constexpr std::uint64_t kMaxJsonInteger = std::uint64_t{1} << 53;
/// Elements allowed in an accessor without a buffer view (all zeros, maybe sparse).
constexpr std::uint64_t kMaxViewlessCount = std::uint64_t{1} << 24;

constexpr std::array<std::string_view, 3> kUnsupportedRequired{
    "KHR_draco_mesh_compression", "EXT_meshopt_compression", "EXT_mesh_gpu_instancing"};

template <typename T>
[[nodiscard]] T load_le(const unsigned char* p) {
    std::array<unsigned char, sizeof(T)> b{};
    std::memcpy(b.data(), p, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) {
        std::reverse(b.begin(), b.end());
    }
    return std::bit_cast<T>(b);
}

[[nodiscard]] std::size_t component_size(std::uint64_t component_type) {
    switch (component_type) {
        case 5120:  // BYTE
        case 5121:  // UNSIGNED_BYTE
            return 1;
        case 5122:  // SHORT
        case 5123:  // UNSIGNED_SHORT
            return 2;
        case 5125:  // UNSIGNED_INT
        case 5126:  // FLOAT
            return 4;
        default:
            return 0;
    }
}

[[nodiscard]] std::size_t type_components(std::string_view type) {
    if (type == "SCALAR") {
        return 1;
    }
    if (type == "VEC2") {
        return 2;
    }
    if (type == "VEC3") {
        return 3;
    }
    if (type == "VEC4" || type == "MAT2") {
        return 4;
    }
    return type == "MAT3" ? 9 : (type == "MAT4" ? 16 : 0);
}

/// One component at `p`; normalized integers map to [0, 1] or [-1, 1] (glTF 3.11).
[[nodiscard]] double decode(std::uint64_t component_type, const unsigned char* p, bool normalized) {
    switch (component_type) {
        case 5120: {
            const double v = load_le<std::int8_t>(p);
            return normalized ? std::max(v / 127.0, -1.0) : v;
        }
        case 5121: {
            const double v = load_le<std::uint8_t>(p);
            return normalized ? v / 255.0 : v;
        }
        case 5122: {
            const double v = load_le<std::int16_t>(p);
            return normalized ? std::max(v / 32767.0, -1.0) : v;
        }
        case 5123: {
            const double v = load_le<std::uint16_t>(p);
            return normalized ? v / 65535.0 : v;
        }
        case 5125: {
            const double v = load_le<std::uint32_t>(p);
            return normalized ? v / 4294967295.0 : v;
        }
        default:
            return load_le<float>(p);
    }
}

[[nodiscard]] bool is_index_type(std::uint64_t component_type) {
    return component_type == 5121 || component_type == 5123 || component_type == 5125;
}

/// Decodes standard base64 (padding optional); nullopt on a character outside the alphabet.
[[nodiscard]] std::optional<std::string> decode_base64(std::string_view text) {
    std::array<int, 256> value{};
    value.fill(-1);
    constexpr std::string_view kAlphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (std::size_t i = 0; i < kAlphabet.size(); ++i) {
        value[static_cast<unsigned char>(kAlphabet[i])] = static_cast<int>(i);
    }
    while (!text.empty() && text.back() == '=') {
        text.remove_suffix(1);
    }
    std::string out;
    out.reserve(text.size() * 3 / 4);
    unsigned accumulator = 0;
    int bits = 0;
    for (char c : text) {
        const int v = value[static_cast<unsigned char>(c)];
        if (v < 0) {
            return std::nullopt;
        }
        accumulator = (accumulator << 6) | static_cast<unsigned>(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(static_cast<char>((accumulator >> bits) & 0xFFu));
        }
    }
    return out;
}

/// Undoes %XX escapes in a relative URI (malformed escapes are kept as they are).
[[nodiscard]] std::string percent_decode(std::string_view uri) {
    std::string out;
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '%' && i + 2 < uri.size()) {
            const std::string hex(uri.substr(i + 1, 2));
            char* end = nullptr;
            const long v = std::strtol(hex.c_str(), &end, 16);
            if (end == hex.c_str() + 2) {
                out.push_back(static_cast<char>(v));
                i += 2;
                continue;
            }
        }
        out.push_back(uri[i]);
    }
    return out;
}

/// `where.key`, or `key` at the top level (`where` empty).
[[nodiscard]] std::string member_path(const std::string& where, std::string_view key) {
    return where.empty() ? std::string(key) : where + "." + std::string(key);
}

[[nodiscard]] std::string index_path(std::string_view array, std::size_t index) {
    return std::string(array) + "[" + std::to_string(index) + "]";
}

}  // namespace

/// A strided run of `count` elements at `data`.
struct GltfDocument::Block {
    const unsigned char* data = nullptr;
    std::size_t stride = 0;
};

GltfDocument::GltfDocument(const std::filesystem::path& path)
    : path_(path.string()), dir_(path.parent_path()) {
    const std::string bytes = read_file_bytes(path);
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c + 32) : c; });
    const bool glb_magic =
        bytes.size() >= 4 &&
        load_le<std::uint32_t>(reinterpret_cast<const unsigned char*>(bytes.data())) == kGlbMagic;
    if (glb_magic) {
        parse_glb(bytes);
    } else if (ext == ".glb") {
        fail("GLB header", "magic is not 'glTF' (not a binary glTF file)");
    } else {
        parse_json(bytes);
    }
    const auto version = json_.contains("asset") && json_["asset"].is_object()
                             ? json_["asset"].value("version", json())
                             : json();
    if (!version.is_string()) {
        fail("asset.version", "missing (is this a glTF 2.0 file?)");
    }
    const auto v = version.get<std::string>();
    if (v.rfind("2.", 0) != 0) {
        fail("asset.version", "'" + v + "' is not a supported glTF version (expected 2.x)");
    }
    if (auto it = json_.find("extensionsRequired"); it != json_.end() && it->is_array()) {
        for (const auto& name : *it) {
            if (name.is_string() &&
                std::find(kUnsupportedRequired.begin(), kUnsupportedRequired.end(),
                          name.get<std::string>()) != kUnsupportedRequired.end()) {
                fail("extensionsRequired",
                     "'" + name.get<std::string>() + "' is required but not supported");
            }
        }
    }
    if (auto it = json_.find("buffers"); it != json_.end() && it->is_array()) {
        buffers_.resize(it->size());
    }
}

void GltfDocument::fail(const std::string& where, const std::string& what) const {
    throw InputError(path_, where + ": " + what);
}

void GltfDocument::parse_glb(const std::string& bytes) {
    const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
    if (bytes.size() < 12) {
        fail("GLB header", "the file has " + std::to_string(bytes.size()) +
                               " bytes, fewer than the 12-byte header");
    }
    const auto version = load_le<std::uint32_t>(data + 4);
    if (version != 2) {
        fail("GLB header", "version " + std::to_string(version) + " (only 2 is supported)");
    }
    const std::size_t length = load_le<std::uint32_t>(data + 8);
    if (length > bytes.size()) {
        fail("GLB header", "length " + std::to_string(length) + " but the file has only " +
                               std::to_string(bytes.size()) + " bytes");
    }
    bool have_json = false;
    std::size_t pos = 12;
    for (int chunk = 0; pos + 8 <= length; ++chunk) {
        const std::size_t chunk_length = load_le<std::uint32_t>(data + pos);
        const auto type = load_le<std::uint32_t>(data + pos + 4);
        const std::string where = "GLB chunk " + std::to_string(chunk);
        if (chunk_length > length - pos - 8) {
            fail(where,
                 "length " + std::to_string(chunk_length) + " runs past the end of the file");
        }
        const std::string_view content(bytes.data() + pos + 8, chunk_length);
        if (chunk == 0) {
            if (type != kGlbChunkJson) {
                fail(where, "the first chunk is not of type JSON");
            }
            parse_json(content);
            have_json = true;
        } else if (chunk == 1 && type == kGlbChunkBin) {
            glb_bin_ = std::string(content);
            has_glb_bin_ = true;
        }
        pos += 8 + chunk_length;
    }
    if (!have_json) {
        fail("GLB header", "no JSON chunk");
    }
}

void GltfDocument::parse_json(std::string_view text) {
    try {
        json_ = json::parse(text);
    } catch (const json::parse_error& e) {
        throw InputError(path_, std::string("malformed JSON: ") + e.what());
    }
    if (!json_.is_object()) {
        fail("JSON", "the top level is not an object");
    }
}

const json& GltfDocument::element(std::string_view array, std::size_t index,
                                  const std::string& where) const {
    const auto it = json_.find(array);
    const std::size_t size = it != json_.end() && it->is_array() ? it->size() : 0;
    if (index >= size) {
        fail(where, index_path(array, index) + " does not exist (the file has " +
                        std::to_string(size) + ")");
    }
    const json& e = (*it)[index];
    if (!e.is_object()) {
        fail(index_path(array, index), "expected an object");
    }
    return e;
}

std::optional<std::uint64_t> GltfDocument::optional_uint(const json& object, std::string_view key,
                                                         const std::string& where) const {
    const auto it = object.find(key);
    if (it == object.end()) {
        return std::nullopt;
    }
    if (it->is_number_unsigned() && it->get<std::uint64_t>() <= kMaxJsonInteger) {
        return it->get<std::uint64_t>();
    }
    if (it->is_number_float()) {
        const double v = it->get<double>();
        if (v >= 0 && v <= static_cast<double>(kMaxJsonInteger) &&
            v == static_cast<double>(static_cast<std::uint64_t>(v))) {
            return static_cast<std::uint64_t>(v);
        }
    }
    fail(member_path(where, key), "expected a non-negative integer, got " + it->dump());
}

std::uint64_t GltfDocument::require_uint(const json& object, std::string_view key,
                                         const std::string& where) const {
    const auto v = optional_uint(object, key, where);
    if (!v) {
        fail(where, "missing '" + std::string(key) + "'");
    }
    return *v;
}

std::optional<std::vector<double>> GltfDocument::optional_numbers(const json& object,
                                                                  std::string_view key,
                                                                  std::size_t n,
                                                                  const std::string& where) const {
    const auto it = object.find(key);
    if (it == object.end()) {
        return std::nullopt;
    }
    if (!it->is_array() || it->size() != n ||
        !std::all_of(it->begin(), it->end(), [](const json& x) { return x.is_number(); })) {
        fail(member_path(where, key), "expected an array of " + std::to_string(n) + " numbers");
    }
    std::vector<double> out;
    out.reserve(n);
    for (const auto& x : *it) {
        out.push_back(x.get<double>());
    }
    return out;
}

const std::string& GltfDocument::buffer(std::size_t index, const std::string& where) {
    const json& b = element("buffers", index, where);
    if (buffers_[index]) {
        return *buffers_[index];
    }
    const std::string self = index_path("buffers", index);
    const std::uint64_t byte_length = require_uint(b, "byteLength", self);
    std::string data;
    const auto uri = b.find("uri");
    if (uri == b.end()) {
        if (index != 0 || !has_glb_bin_) {
            fail(self, "has no uri and the file has no GLB binary chunk");
        }
        data = glb_bin_;
    } else if (!uri->is_string()) {
        fail(self + ".uri", "expected a string");
    } else if (const auto text = uri->get<std::string>(); text.rfind("data:", 0) == 0) {
        const auto comma = text.find(',');
        if (comma == std::string::npos || comma < 7 || text.compare(comma - 7, 7, ";base64") != 0) {
            fail(self + ".uri", "only base64 data URIs are supported");
        }
        auto decoded = decode_base64(std::string_view(text).substr(comma + 1));
        if (!decoded) {
            fail(self + ".uri", "invalid base64 data");
        }
        data = std::move(*decoded);
    } else {
        const std::string relative = percent_decode(text);
        try {
            data = read_file_bytes(dir_ / relative);
        } catch (const InputError& e) {
            fail(self + ".uri", "cannot read buffer file '" + relative + "' (" + e.what() + ")");
        }
    }
    if (data.size() < byte_length) {
        fail(self, "byteLength " + std::to_string(byte_length) + " but the data has only " +
                       std::to_string(data.size()) + " bytes");
    }
    data.resize(static_cast<std::size_t>(byte_length));
    buffers_[index] = std::move(data);
    return *buffers_[index];
}

GltfDocument::Block GltfDocument::view_block(const json& holder, const std::string& where,
                                             std::uint64_t count, std::size_t element_size,
                                             bool strided) {
    const auto view_index = static_cast<std::size_t>(require_uint(holder, "bufferView", where));
    const json& view = element("bufferViews", view_index, where + ".bufferView");
    const std::string self = index_path("bufferViews", view_index);
    const auto buffer_index = static_cast<std::size_t>(require_uint(view, "buffer", self));
    const std::uint64_t view_length = require_uint(view, "byteLength", self);
    const std::uint64_t view_offset = optional_uint(view, "byteOffset", self).value_or(0);
    const std::string& data = buffer(buffer_index, self + ".buffer");
    if (view_offset > data.size() || view_length > data.size() - view_offset) {
        fail(self, "byteOffset " + std::to_string(view_offset) + " + byteLength " +
                       std::to_string(view_length) + " runs past the end of " +
                       index_path("buffers", buffer_index) + " (" + std::to_string(data.size()) +
                       " bytes)");
    }
    std::uint64_t stride = element_size;
    if (strided) {
        if (const auto s = optional_uint(view, "byteStride", self)) {
            if (*s < element_size) {
                fail(self, "byteStride " + std::to_string(*s) + " is smaller than the " +
                               std::to_string(element_size) + "-byte elements of " + where);
            }
            stride = *s;
        }
    }
    const std::uint64_t offset = optional_uint(holder, "byteOffset", where).value_or(0);
    if (count > 0) {
        const bool fits = offset <= view_length && element_size <= view_length - offset &&
                          (count - 1) <= (view_length - offset - element_size) / stride;
        if (!fits) {
            fail(where, "byteOffset " + std::to_string(offset) + " + " + std::to_string(count) +
                            " elements of " + std::to_string(element_size) + " bytes (stride " +
                            std::to_string(stride) + ") run past the end of " + self + " (" +
                            std::to_string(view_length) + " bytes)");
        }
    }
    const auto* base = reinterpret_cast<const unsigned char*>(data.data());
    return {base + view_offset + offset, static_cast<std::size_t>(stride)};
}

std::vector<double> GltfDocument::read_accessor(std::size_t index, std::string_view type,
                                                bool integer_only) {
    const std::string where = index_path("accessors", index);
    const json& acc = json_["accessors"][index];
    const std::uint64_t component_type = require_uint(acc, "componentType", where);
    const std::size_t size = component_size(component_type);
    if (size == 0) {
        fail(where, "componentType " + std::to_string(component_type) + " is not a glTF type");
    }
    const auto type_it = acc.find("type");
    if (type_it == acc.end() || !type_it->is_string()) {
        fail(where, "missing 'type'");
    }
    if (type_it->get<std::string>() != type) {
        fail(where,
             "type '" + type_it->get<std::string>() + "', expected '" + std::string(type) + "'");
    }
    const bool normalized = acc.value("normalized", false);
    if (integer_only && (!is_index_type(component_type) || normalized)) {
        fail(where, "componentType " + std::to_string(component_type) +
                        " is not an unsigned integer type (5121, 5123 or 5125)");
    }
    if (!integer_only && component_type == 5125) {
        fail(where, "componentType 5125 (unsigned int) is not allowed here");
    }
    const std::size_t components = type_components(type);
    const std::uint64_t count = require_uint(acc, "count", where);
    const bool has_view = acc.contains("bufferView");
    if (!has_view && count > kMaxViewlessCount) {
        fail(where, "count " + std::to_string(count) + " without a bufferView is too large");
    }
    const std::size_t element_size = size * components;
    std::vector<double> out;
    if (has_view) {
        const Block block = view_block(acc, where, count, element_size, true);
        out.resize(static_cast<std::size_t>(count) * components);
        for (std::size_t i = 0; i < count; ++i) {
            const unsigned char* p = block.data + i * block.stride;
            for (std::size_t c = 0; c < components; ++c) {
                out[i * components + c] = decode(component_type, p + c * size, normalized);
            }
        }
    } else {
        out.assign(static_cast<std::size_t>(count) * components, 0.0);
    }
    const auto sparse_it = acc.find("sparse");
    if (sparse_it == acc.end()) {
        return out;
    }
    const std::string sparse_where = where + ".sparse";
    const json& sparse = *sparse_it;
    const std::uint64_t sparse_count = require_uint(sparse, "count", sparse_where);
    if (sparse_count > count) {
        fail(sparse_where, "count " + std::to_string(sparse_count) + " exceeds the accessor's " +
                               std::to_string(count));
    }
    const auto indices_it = sparse.find("indices");
    const auto values_it = sparse.find("values");
    if (indices_it == sparse.end() || !indices_it->is_object() || values_it == sparse.end() ||
        !values_it->is_object()) {
        fail(sparse_where, "expected objects 'indices' and 'values'");
    }
    const std::string indices_where = sparse_where + ".indices";
    const std::uint64_t index_type = require_uint(*indices_it, "componentType", indices_where);
    if (!is_index_type(index_type)) {
        fail(indices_where,
             "componentType " + std::to_string(index_type) + " is not an unsigned integer type");
    }
    const std::size_t index_size = component_size(index_type);
    const Block indices = view_block(*indices_it, indices_where, sparse_count, index_size, false);
    const Block values =
        view_block(*values_it, sparse_where + ".values", sparse_count, element_size, false);
    for (std::size_t k = 0; k < sparse_count; ++k) {
        const auto target =
            static_cast<std::uint64_t>(decode(index_type, indices.data + k * index_size, false));
        if (target >= count) {
            fail(indices_where, "index " + std::to_string(target) + " out of range (count " +
                                    std::to_string(count) + ")");
        }
        for (std::size_t c = 0; c < components; ++c) {
            out[target * components + c] =
                decode(component_type, values.data + k * element_size + c * size, normalized);
        }
    }
    return out;
}

std::vector<Vec3d> GltfDocument::read_positions(std::size_t index, const std::string& where) {
    static_cast<void>(element("accessors", index, where));
    const std::vector<double> flat = read_accessor(index, "VEC3", false);
    std::vector<Vec3d> out(flat.size() / 3);
    for (std::size_t i = 0; i < out.size(); ++i) {
        out[i] = {flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]};
    }
    return out;
}

std::vector<std::uint32_t> GltfDocument::read_indices(std::size_t index, std::size_t vertex_count,
                                                      const std::string& where) {
    static_cast<void>(element("accessors", index, where));
    const std::vector<double> flat = read_accessor(index, "SCALAR", true);
    std::vector<std::uint32_t> out(flat.size());
    for (std::size_t i = 0; i < flat.size(); ++i) {
        if (flat[i] >= static_cast<double>(vertex_count)) {
            fail(index_path("accessors", index),
                 "index " + std::to_string(static_cast<std::uint64_t>(flat[i])) +
                     " out of range (" + std::to_string(vertex_count) + " vertices)");
        }
        out[i] = static_cast<std::uint32_t>(flat[i]);
    }
    return out;
}

}  // namespace beamtrace::detail
