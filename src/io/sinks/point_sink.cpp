#include "beamtrace/io/point_sink.hpp"

namespace beamtrace {

std::unique_ptr<SinkBuffer> PointSink::make_buffer() const {
    return std::make_unique<ByteBuffer>();
}

}  // namespace beamtrace
