// The layered WAVEPACKET14 item (version 3) of point formats 9 and 10: the wave packet
// descriptor index, the byte offset and size of the packet, the return point location and the
// x(t), y(t), z(t) direction (29 bytes), in one layer. The offset is coded as "same", "after the
// last packet", a difference from the last, or raw; the rest against the channel's last values.
// Channel switches follow the RGB14 rule (layered_rgb.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>

#include "laz/arithmetic_model.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/layered_layer.hpp"

namespace beamtrace::laz {

class WavePacket14Decoder {
  public:
    static constexpr std::size_t kBytes = 29;

    WavePacket14Decoder(const std::uint8_t* first, std::span<const std::uint8_t> layer,
                        unsigned channel);
    ~WavePacket14Decoder();
    WavePacket14Decoder(const WavePacket14Decoder&) = delete;
    WavePacket14Decoder& operator=(const WavePacket14Decoder&) = delete;
    WavePacket14Decoder(WavePacket14Decoder&&) = delete;
    WavePacket14Decoder& operator=(WavePacket14Decoder&&) = delete;

    void decode(std::uint8_t* out, unsigned channel);

  private:
    struct Context;
    void start_context(unsigned channel, const std::array<std::uint8_t, kBytes>& from);

    Layer layer_;
    std::array<std::unique_ptr<Context>, 4> contexts_;
    unsigned current_ = 0;
};

}  // namespace beamtrace::laz
