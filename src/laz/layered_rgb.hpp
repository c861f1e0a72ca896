// The layered RGB14 and RGBNIR14 items (version 3): red, green, blue (one layer) and, for
// RGBNIR14, near infrared (a second layer), coded byte by byte against the channel's last
// colour.
//
// A quirk of the format, kept by every LASzip-compatible coder: on a switch to a scanner channel
// that already has a context, the predictions still come from the previous channel's last
// colour (and that colour is what gets updated); only a channel seen for the first time starts
// from a copy.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>

#include "laz/arithmetic_model.hpp"
#include "laz/layered_layer.hpp"

namespace beamtrace::laz {

class Rgb14Decoder {
  public:
    /// `first`: the item's bytes in the chunk's first record (6, or 8 with `nir`); `rgb`, `nir`:
    /// the layers (`nir` ignored without NIR).
    Rgb14Decoder(const std::uint8_t* first, bool nir, std::span<const std::uint8_t> rgb,
                 std::span<const std::uint8_t> nir_layer, unsigned channel);
    ~Rgb14Decoder();
    Rgb14Decoder(const Rgb14Decoder&) = delete;
    Rgb14Decoder& operator=(const Rgb14Decoder&) = delete;
    Rgb14Decoder(Rgb14Decoder&&) = delete;
    Rgb14Decoder& operator=(Rgb14Decoder&&) = delete;

    /// Decodes the item of the next record, of scanner channel `channel`, into `out`.
    void decode(std::uint8_t* out, unsigned channel);

  private:
    struct Context;
    void start_context(unsigned channel, const std::array<std::uint16_t, 4>& from);
    void decode_rgb(Context& c, std::array<std::uint16_t, 4>& last);
    void decode_nir(Context& c, std::array<std::uint16_t, 4>& last);

    Layer rgb_;
    std::optional<Layer> nir_;
    std::array<std::unique_ptr<Context>, 4> contexts_;
    unsigned current_ = 0;
};

}  // namespace beamtrace::laz
