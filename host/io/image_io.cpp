// OpenImageIO behind a C interface; nothing else lives here.
#include "image_io.h"
#include "../util/colour.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace
{

bool keeps_floats(const std::string &path)
{
    std::string ext = OIIO::Filesystem::extension(path, false);
    for (auto &c : ext) c = (char)std::tolower((unsigned char)c);
    return ext == "exr" || ext == "hdr";
}

float linear_to_srgb(float v)
{
    if (!(v > 0.0f)) return 0.0f;
    if (v >= 1.0f) return 1.0f;
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

} // namespace

extern "C" lvcl_error lvcl_image_write(const char *path, const float *rgb, int width, int height, float exposure,
                                       lvcl_status *st)
{
    try {
        auto out = OIIO::ImageOutput::create(path);
        if (!out) return lvcl_fail(st, LVCL_ERR_IO, "cannot write %s: unknown image format", path);
        size_t n = (size_t)width * height * 3;
        bool ok;
        if (keeps_floats(path)) {
            OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::FLOAT);
            spec.attribute("compression", "zip");
            ok = out->open(path, spec) && out->write_image(OIIO::TypeDesc::FLOAT, rgb);
        } else {
            std::vector<unsigned char> bytes(n);
            float scale = std::exp2(exposure);
            for (size_t i = 0; i < n; i++)
                bytes[i] = (unsigned char)std::lround(255.0f * linear_to_srgb(rgb[i] * scale));
            OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
            ok = out->open(path, spec) && out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
        }
        if (!ok) {
            std::string msg = out->geterror();
            return lvcl_fail(st, LVCL_ERR_IO, "cannot write %s: %s", path, msg.c_str());
        }
        out->close();
        return LVCL_OK;
    } catch (...) {
        return lvcl_fail(st, LVCL_ERR_IO, "cannot write %s", path);
    }
}

extern "C" lvcl_error lvcl_image_format_check(const char *path, lvcl_status *st)
{
    try {
        if (!OIIO::ImageOutput::create(path))
            return lvcl_fail(st, LVCL_ERR_IO, "cannot write %s: unknown image format", path);
        return LVCL_OK;
    } catch (...) {
        return lvcl_fail(st, LVCL_ERR_IO, "cannot write %s: unknown image format", path);
    }
}

extern "C" lvcl_error lvcl_image_read(const char *path, float **rgb, int *width, int *height, lvcl_status *st)
{
    *rgb = nullptr;
    try {
        auto in = OIIO::ImageInput::open(path);
        if (!in) return lvcl_fail(st, LVCL_ERR_IO, "cannot read image %s", path);
        const OIIO::ImageSpec &spec = in->spec();
        int channels = spec.nchannels;
        std::vector<float> all((size_t)spec.width * spec.height * channels);
        if (!in->read_image(0, 0, 0, channels, OIIO::TypeDesc::FLOAT, all.data()))
            return lvcl_fail(st, LVCL_ERR_IO, "cannot read image %s", path);
        bool srgb = spec.format == OIIO::TypeDesc::UINT8;
        size_t pixels = (size_t)spec.width * spec.height;
        float *out = (float *)std::malloc(pixels * 3 * sizeof(float));
        if (!out) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of memory reading %s", path);
        for (size_t i = 0; i < pixels; i++)
            for (int c = 0; c < 3; c++) {
                float v = all[i * channels + (c < channels ? c : 0)];
                if (srgb) v = (float)lvcl_srgb_to_linear(v);
                out[3 * i + c] = v;
            }
        *rgb = out;
        *width = spec.width;
        *height = spec.height;
        in->close();
        return LVCL_OK;
    } catch (...) {
        return lvcl_fail(st, LVCL_ERR_IO, "cannot read image %s", path);
    }
}
