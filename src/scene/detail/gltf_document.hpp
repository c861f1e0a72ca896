// A parsed glTF 2.0 document: its JSON, its buffers (loaded on first use) and typed accessor
// reads, with every error reported as InputError(file, "json.path: what").
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "beamtrace/core/vec3.hpp"

namespace beamtrace::detail {

class GltfDocument {
  public:
    /// Reads `path`: a GLB container if it starts with the magic "glTF", JSON text otherwise.
    explicit GltfDocument(const std::filesystem::path& path);

    [[nodiscard]] const nlohmann::json& root() const { return json_; }

    /// Throws InputError(file, where + ": " + what).
    [[noreturn]] void fail(const std::string& where, const std::string& what) const;

    /// `json()[array][index]`, which must be an object; `where` names the reference.
    [[nodiscard]] const nlohmann::json& element(std::string_view array, std::size_t index,
                                                const std::string& where) const;
    /// `object[key]` as a non-negative integer, or nullopt when absent.
    [[nodiscard]] std::optional<std::uint64_t> optional_uint(const nlohmann::json& object,
                                                             std::string_view key,
                                                             const std::string& where) const;
    [[nodiscard]] std::uint64_t require_uint(const nlohmann::json& object, std::string_view key,
                                             const std::string& where) const;
    /// `object[key]` as `n` numbers, or nullopt when absent.
    [[nodiscard]] std::optional<std::vector<double>> optional_numbers(
        const nlohmann::json& object, std::string_view key, std::size_t n,
        const std::string& where) const;

    /// The positions of accessor `index` (VEC3 float, or integer, normalized or not); `where`
    /// names the reference to it.
    [[nodiscard]] std::vector<Vec3d> read_positions(std::size_t index, const std::string& where);
    /// The indices of accessor `index` (SCALAR u8/u16/u32), each checked to be below
    /// `vertex_count`; `where` names the reference to it.
    [[nodiscard]] std::vector<std::uint32_t> read_indices(std::size_t index,
                                                          std::size_t vertex_count,
                                                          const std::string& where);

  private:
    struct Block;  // a strided run of elements inside a buffer
    void parse_glb(const std::string& bytes);
    void parse_json(std::string_view text);
    [[nodiscard]] const std::string& buffer(std::size_t index, const std::string& where);
    [[nodiscard]] Block view_block(const nlohmann::json& holder, const std::string& where,
                                   std::uint64_t count, std::size_t element_size, bool strided);
    /// Every component of accessor `index` as double, `components` per element.
    [[nodiscard]] std::vector<double> read_accessor(std::size_t index, std::string_view type,
                                                    bool integer_only);

    std::string path_;
    std::filesystem::path dir_;
    nlohmann::json json_;
    std::string glb_bin_;
    bool has_glb_bin_ = false;
    std::vector<std::optional<std::string>> buffers_;
};

}  // namespace beamtrace::detail
