// The layered BYTE14 item (version 3): the extra bytes of a record, one layer per byte, each byte
// coded as its difference from the channel's last value of that byte. On a channel switch the
// last values follow the same rule as RGB14 (see layered_rgb.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "laz/arithmetic_model.hpp"
#include "laz/layered_layer.hpp"

namespace beamtrace::laz {

class Byte14Decoder {
  public:
    /// `first`: the item's `layers.size()` bytes in the chunk's first record.
    Byte14Decoder(const std::uint8_t* first, std::span<const std::span<const std::uint8_t>> layers,
                  unsigned channel);
    ~Byte14Decoder();
    Byte14Decoder(const Byte14Decoder&) = delete;
    Byte14Decoder& operator=(const Byte14Decoder&) = delete;
    Byte14Decoder(Byte14Decoder&&) = delete;
    Byte14Decoder& operator=(Byte14Decoder&&) = delete;

    void decode(std::uint8_t* out, unsigned channel);

  private:
    struct Context {
        std::vector<std::uint8_t> last;
        std::vector<std::optional<ArithmeticModel>> models;  ///< only for coded layers
    };
    void start_context(unsigned channel, const std::vector<std::uint8_t>& from);

    std::vector<Layer> layers_;
    std::vector<std::size_t> coded_;  ///< the bytes whose layer is coded
    std::array<std::unique_ptr<Context>, 4> contexts_;
    unsigned current_ = 0;
};

}  // namespace beamtrace::laz
