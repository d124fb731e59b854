// rayproof/render/image.hpp — 8-bit RGB images: PNG (libpng) and binary PPM (P6) in and
// out, and the comparisons the golden-image tests and `render --diff` use.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rayproof::render {

struct Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb;  // row-major, top row first, 3 bytes per pixel
    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(std::size_t(w) * std::size_t(h) * 3, 0) {}
    std::uint8_t* at(int x, int y) { return &rgb[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3]; }
    const std::uint8_t* at(int x, int y) const {
        return &rgb[(std::size_t(y) * std::size_t(width) + std::size_t(x)) * 3];
    }
};

// Linear radiance in [0, 1] to a byte: round(255·clamp(v)); NaN gives 0.
std::uint8_t to_byte(double v);

// Writers and readers return "" on success, otherwise a message naming the file.
// write_image picks the format from the extension: .png or .ppm (case-insensitive).
std::string write_image(const Image& img, const std::string& path);
std::string write_png(const Image& img, const std::string& path);
std::string write_ppm(const Image& img, const std::string& path);
std::string read_image(const std::string& path, Image& out);
bool has_image_extension(const std::string& path);

struct ImageComparison {
    bool same_size = false;
    long long differing_pixels = 0;  // pixels whose largest channel difference exceeds the threshold
    int max_channel_difference = 0;
    double mean_abs_difference = 0;  // mean over every channel of every pixel, in 1/255
    double psnr = 0;  // dB; +inf when identical
};
ImageComparison compare(const Image& a, const Image& b, int threshold = 0);

// The picture `render --diff` writes: a dimmed grey copy of a, with every pixel where a
// and b differ (largest channel difference > threshold) in bright magenta.
Image diff_image(const Image& a, const Image& b, int threshold = 0);

}  // namespace rayproof::render
