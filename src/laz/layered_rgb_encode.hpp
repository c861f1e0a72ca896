// The encoder of the layered RGB14 and RGBNIR14 items (version 3), LASzip's
// LASwriteItemCompressed_RGB14_v3 / RGBNIR14_v3: the mirror of Rgb14Decoder (layered_rgb.hpp),
// with its quirk: on a switch to a channel that already has a context the previous channel's
// last colour stays the prediction (and is what gets updated).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "laz/layered_encode_layer.hpp"

namespace beamtrace::laz {

class Rgb14Encoder {
  public:
    /// `first`: the item's bytes in the chunk's first record (6, or 8 with `nir`).
    Rgb14Encoder(const std::uint8_t* first, bool nir, unsigned channel);
    ~Rgb14Encoder();
    Rgb14Encoder(const Rgb14Encoder&) = delete;
    Rgb14Encoder& operator=(const Rgb14Encoder&) = delete;
    Rgb14Encoder(Rgb14Encoder&&) = delete;
    Rgb14Encoder& operator=(Rgb14Encoder&&) = delete;

    /// Encodes the item of the next record, of scanner channel `channel`.
    void encode(const std::uint8_t* item, unsigned channel);

    /// Ends the layers and appends their bytes (1, or 2 with NIR) to `layers`.
    void finish(std::vector<std::span<const std::uint8_t>>& layers);

  private:
    struct Context;
    void start_context(unsigned channel, const std::array<std::uint16_t, 4>& from);
    void encode_rgb(Context& c, const std::array<std::uint16_t, 4>& last,
                    const std::array<std::uint16_t, 4>& now);
    void encode_nir(Context& c, std::uint16_t last, std::uint16_t now);

    bool nir_;
    EncodeLayer rgb_layer_;
    EncodeLayer nir_layer_;
    std::array<std::unique_ptr<Context>, 4> contexts_;
    unsigned current_ = 0;
};

}  // namespace beamtrace::laz
