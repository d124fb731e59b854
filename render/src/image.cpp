// Image files (PNG through libpng, binary PPM) and image comparison.
#include <rayproof/render/image.hpp>

#include <png.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>

namespace rayproof::render {

namespace {

std::string lower_extension(const std::string& path) {
    const auto dot = path.find_last_of('.');
    const auto slash = path.find_last_of('/');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    std::string ext = path.substr(dot + 1);
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

struct FileCloser {
    void operator()(std::FILE* f) const {
        if (f) std::fclose(f);
    }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

std::string os_error(const std::string& what, const std::string& path, int error = errno) {
    return what + " '" + path + "': " + std::strerror(error != 0 ? error : EIO);
}

// libpng reports errors through longjmp; these handlers keep it inside this file.
void png_error_fn(png_structp png, png_const_charp msg) {
    auto* out = static_cast<std::string*>(png_get_error_ptr(png));
    if (out) *out = msg;
    png_longjmp(png, 1);
}
void png_warning_fn(png_structp, png_const_charp) {}

}  // namespace

std::uint8_t to_byte(double v) {
    if (!(v > 0)) return 0;  // also NaN
    if (v >= 1) return 255;
    return std::uint8_t(std::lround(v * 255));
}

bool has_image_extension(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == "png" || ext == "ppm";
}

std::string write_image(const Image& img, const std::string& path) {
    const std::string ext = lower_extension(path);
    if (ext == "png") return write_png(img, path);
    if (ext == "ppm") return write_ppm(img, path);
    return "cannot tell the image format of '" + path + "': use a .png or .ppm file name";
}

// Every write, and the close that flushes the last buffer, is checked: a full disk shows
// only there ("cannot write 'PATH': No space left on device").
std::string write_ppm(const Image& img, const std::string& path) {
    File f(std::fopen(path.c_str(), "wb"));
    if (!f) return os_error("cannot open", path);
    errno = 0;
    if (std::fprintf(f.get(), "P6\n%d %d\n255\n", img.width, img.height) < 0) return os_error("cannot write", path);
    if (std::fwrite(img.rgb.data(), 1, img.rgb.size(), f.get()) != img.rgb.size()) return os_error("cannot write", path);
    if (std::fclose(f.release()) != 0) return os_error("cannot write", path);
    return "";
}

namespace {

// libpng's output, through stdio, keeping the errno of a failed write or flush (libpng's
// own writer reports only "Write Error").
struct PngOutput {
    std::FILE* f;
    int error = 0;
};
void png_write_fn(png_structp png, png_bytep data, png_size_t n) {
    auto* out = static_cast<PngOutput*>(png_get_io_ptr(png));
    errno = 0;
    if (std::fwrite(data, 1, n, out->f) != n) {
        out->error = errno != 0 ? errno : EIO;
        png_error(png, "write failed");
    }
}
void png_flush_fn(png_structp png) {
    auto* out = static_cast<PngOutput*>(png_get_io_ptr(png));
    errno = 0;
    if (std::fflush(out->f) != 0) {
        out->error = errno != 0 ? errno : EIO;
        png_error(png, "write failed");
    }
}

// The setjmp frames below hold only pointers and plain values that are not modified
// after setjmp, so a libpng error (longjmp) leaves nothing indeterminate.
bool png_write_rows(png_structp png, png_infop info, PngOutput* out, const Image* img) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_set_write_fn(png, out, png_write_fn, png_flush_fn);
    png_set_IHDR(png, info, png_uint_32(img->width), png_uint_32(img->height), 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < img->height; ++y) png_write_row(png, const_cast<png_bytep>(img->at(0, y)));
    png_write_end(png, nullptr);
    return true;
}

// Reads the header, then (when the layout is supported) the rows into *out.
// Returns 0 on success, 1 on a libpng error, 2 on an unsupported layout.
int png_read_rows(png_structp png, png_infop info, std::FILE* f, Image* out) {
    if (setjmp(png_jmpbuf(png))) return 1;
    png_init_io(png, f);
    png_read_info(png, info);
    const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    const int depth = png_get_bit_depth(png, info), type = png_get_color_type(png, info);
    if (depth == 16) png_set_strip_16(png);
    if (type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
    if (type == PNG_COLOR_TYPE_GRAY || type == PNG_COLOR_TYPE_GRAY_ALPHA) png_set_gray_to_rgb(png);
    if (type & PNG_COLOR_MASK_ALPHA) png_set_strip_alpha(png);
    if (depth < 8) png_set_expand(png);
    png_read_update_info(png, info);
    if (w == 0 || h == 0 || w > 65536 || h > 65536 || png_get_rowbytes(png, info) != w * 3) return 2;
    *out = Image(int(w), int(h));
    for (png_uint_32 y = 0; y < h; ++y) png_read_row(png, out->at(0, int(y)), nullptr);
    return 0;
}

}  // namespace

std::string write_png(const Image& img, const std::string& path) {
    File f(std::fopen(path.c_str(), "wb"));
    if (!f) return os_error("cannot open", path);
    std::string err;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &err, png_error_fn, png_warning_fn);
    if (!png) return "cannot write '" + path + "': out of memory";
    png_infop info = png_create_info_struct(png);
    PngOutput out{f.get()};
    const bool ok = info && png_write_rows(png, info, &out, &img);
    png_destroy_write_struct(&png, &info);
    if (!ok && out.error != 0) return os_error("cannot write", path, out.error);
    if (!ok) return "cannot write '" + path + "': " + (err.empty() ? "libpng error" : err);
    errno = 0;
    if (std::fclose(f.release()) != 0) return os_error("cannot write", path);
    return "";
}

namespace {

std::string read_ppm(const std::string& path, Image& out) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return os_error("cannot open", path);
    std::string magic;
    long long w = 0, h = 0, maxval = 0;
    auto skip = [&] {
        for (;;) {
            const int c = in.peek();
            if (c == '#') {
                std::string line;
                std::getline(in, line);
            } else if (std::isspace(c)) {
                in.get();
            } else {
                return;
            }
        }
    };
    in >> magic;
    skip();
    in >> w;
    skip();
    in >> h;
    skip();
    in >> maxval;
    if (!in || magic != "P6" || maxval != 255 || w <= 0 || h <= 0 || w > 65536 || h > 65536)
        return "'" + path + "' is not an 8-bit binary PPM (P6) file";
    in.get();
    Image img(static_cast<int>(w), static_cast<int>(h));
    in.read(reinterpret_cast<char*>(img.rgb.data()), std::streamsize(img.rgb.size()));
    if (!in) return "'" + path + "': truncated PPM data";
    out = std::move(img);
    return "";
}

std::string read_png(const std::string& path, Image& out) {
    File f(std::fopen(path.c_str(), "rb"));
    if (!f) return os_error("cannot open", path);
    std::string err;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &err, png_error_fn, png_warning_fn);
    if (!png) return "cannot read '" + path + "': out of memory";
    png_infop info = png_create_info_struct(png);
    Image img;
    const int rc = info ? png_read_rows(png, info, f.get(), &img) : 1;
    png_destroy_read_struct(&png, &info, nullptr);
    if (rc == 1) return "cannot read '" + path + "': " + (err.empty() ? "libpng error" : err);
    if (rc == 2) return "'" + path + "': unsupported PNG layout";
    out = std::move(img);
    return "";
}

}  // namespace

std::string read_image(const std::string& path, Image& out) {
    const std::string ext = lower_extension(path);
    if (ext == "png") return read_png(path, out);
    if (ext == "ppm") return read_ppm(path, out);
    return "cannot tell the image format of '" + path + "': use a .png or .ppm file name";
}

ImageComparison compare(const Image& a, const Image& b, int threshold) {
    ImageComparison c;
    c.same_size = a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size();
    if (!c.same_size) return c;
    double sq = 0, sum = 0;
    for (std::size_t i = 0; i < a.rgb.size(); i += 3) {
        int m = 0;
        for (std::size_t k = 0; k < 3; ++k) {
            const int d = std::abs(int(a.rgb[i + k]) - int(b.rgb[i + k]));
            m = std::max(m, d);
            sq += double(d) * d;
            sum += d;
        }
        c.max_channel_difference = std::max(c.max_channel_difference, m);
        if (m > threshold) ++c.differing_pixels;
    }
    const double mse = a.rgb.empty() ? 0 : sq / double(a.rgb.size());
    c.mean_abs_difference = a.rgb.empty() ? 0 : sum / double(a.rgb.size());
    c.psnr = mse == 0 ? std::numeric_limits<double>::infinity() : 10 * std::log10(255.0 * 255.0 / mse);
    return c;
}

Image diff_image(const Image& a, const Image& b, int threshold) {
    Image d(a.width, a.height);
    if (a.width != b.width || a.height != b.height) return d;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            const std::uint8_t* pa = a.at(x, y);
            const std::uint8_t* pb = b.at(x, y);
            std::uint8_t* pd = d.at(x, y);
            int m = 0;
            for (int k = 0; k < 3; ++k) m = std::max(m, std::abs(int(pa[k]) - int(pb[k])));
            if (m > threshold) {
                pd[0] = 255, pd[1] = 0, pd[2] = 255;
            } else {
                const int grey = (int(pa[0]) * 30 + int(pa[1]) * 59 + int(pa[2]) * 11) / 100;
                pd[0] = pd[1] = pd[2] = std::uint8_t(grey * 35 / 100);
            }
        }
    return d;
}

}  // namespace rayproof::render
