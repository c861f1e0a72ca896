// The encoder of the layered WAVEPACKET14 item (version 3), LASzip's
// LASwriteItemCompressed_WAVEPACKET14_v3: the mirror of WavePacket14Decoder
// (layered_wavepacket.hpp), one layer, channel switches as in RGB14.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "laz/layered_encode_layer.hpp"

namespace beamtrace::laz {

class WavePacket14Encoder {
  public:
    static constexpr std::size_t kBytes = 29;

    WavePacket14Encoder(const std::uint8_t* first, unsigned channel);
    ~WavePacket14Encoder();
    WavePacket14Encoder(const WavePacket14Encoder&) = delete;
    WavePacket14Encoder& operator=(const WavePacket14Encoder&) = delete;
    WavePacket14Encoder(WavePacket14Encoder&&) = delete;
    WavePacket14Encoder& operator=(WavePacket14Encoder&&) = delete;

    void encode(const std::uint8_t* item, unsigned channel);

    /// Ends the layer and appends its bytes to `layers`.
    void finish(std::vector<std::span<const std::uint8_t>>& layers);

  private:
    struct Context;
    void start_context(unsigned channel, const std::array<std::uint8_t, kBytes>& from);
    void encode_offset(Context& c, const std::uint8_t* last, const std::uint8_t* item);

    EncodeLayer layer_;
    std::array<std::unique_ptr<Context>, 4> contexts_;
    unsigned current_ = 0;
};

}  // namespace beamtrace::laz
