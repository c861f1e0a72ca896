#include "beamtrace/io/png_reader.hpp"

#include <png.h>

#include <cstring>
#include <string>

#include "beamtrace/core/error.hpp"

namespace beamtrace {

RgbImage read_png_rgb8(const std::filesystem::path& path) {
    // libpng's simplified API: no setjmp here, errors come back in image.message.
    png_image image;
    std::memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    if (png_image_begin_read_from_file(&image, path.c_str()) == 0) {
        throw InputError(path.string(), std::string("cannot read PNG: ") + image.message);
    }
    image.format = PNG_FORMAT_RGB;
    RgbImage out;
    out.width = static_cast<int>(image.width);
    out.height = static_cast<int>(image.height);
    out.rgb.resize(PNG_IMAGE_SIZE(image));
    if (png_image_finish_read(&image, nullptr, out.rgb.data(), 0, nullptr) == 0) {
        const std::string message = image.message;
        png_image_free(&image);
        throw InputError(path.string(), "cannot decode PNG: " + message);
    }
    return out;
}

}  // namespace beamtrace
