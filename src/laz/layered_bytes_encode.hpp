// The encoder of the layered BYTE14 item (version 3), LASzip's LASwriteItemCompressed_BYTE14_v3:
// the mirror of Byte14Decoder (layered_bytes.hpp), one layer per extra byte, each byte coded as
// its difference from the channel's last value (channel switches as in RGB14).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "laz/arithmetic_model.hpp"
#include "laz/layered_encode_layer.hpp"

namespace beamtrace::laz {

class Byte14Encoder {
  public:
    /// `first`: the item's `size` bytes in the chunk's first record.
    Byte14Encoder(const std::uint8_t* first, std::size_t size, unsigned channel);
    ~Byte14Encoder();
    Byte14Encoder(const Byte14Encoder&) = delete;
    Byte14Encoder& operator=(const Byte14Encoder&) = delete;
    Byte14Encoder(Byte14Encoder&&) = delete;
    Byte14Encoder& operator=(Byte14Encoder&&) = delete;

    void encode(const std::uint8_t* item, unsigned channel);

    /// Ends the layers and appends their bytes (one per extra byte) to `layers`.
    void finish(std::vector<std::span<const std::uint8_t>>& layers);

  private:
    struct Context {
        std::vector<std::uint8_t> last;
        std::vector<ArithmeticModel> models;
    };
    void start_context(unsigned channel, const std::vector<std::uint8_t>& from);

    std::vector<std::unique_ptr<EncodeLayer>> layers_;
    std::array<std::unique_ptr<Context>, 4> contexts_;
    unsigned current_ = 0;
};

}  // namespace beamtrace::laz
