// Image files and comparisons: PNG and binary PPM round trips (every byte back), the
// format chosen by extension, clear errors for a missing file, an unknown extension and
// a file that is not an image, to_byte rounding and NaN, compare() counts and PSNR,
// and the diff picture.
#include "render_support.hpp"

#include <cmath>
#include <fstream>
#include <random>

namespace rayproof::render::testing {
namespace {

Image noise(int w, int h, unsigned seed) {
    std::mt19937 rng(seed);
    Image img(w, h);
    for (auto& b : img.rgb) b = std::uint8_t(rng() & 0xff);
    return img;
}

TEST(ImageFiles, PngAndPpmRoundTrip) {
    const Image img = noise(17, 9, 7);
    for (const char* ext : {"png", "ppm", "PNG"}) {
        const std::string path = scratch(std::string("roundtrip.") + ext);
        ASSERT_EQ(write_image(img, path), "");
        Image back;
        ASSERT_EQ(read_image(path, back), "");
        EXPECT_EQ(back.width, 17);
        EXPECT_EQ(back.height, 9);
        EXPECT_EQ(back.rgb, img.rgb) << ext;
    }
}

TEST(ImageFiles, PpmIsBinaryP6) {
    Image img(2, 1);
    img.rgb = {1, 2, 3, 250, 251, 252};
    const std::string path = scratch("p6.ppm");
    ASSERT_EQ(write_ppm(img, path), "");
    std::ifstream in(path, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_EQ(bytes, std::string("P6\n2 1\n255\n\x01\x02\x03\xfa\xfb\xfc", 17));
}

TEST(ImageFiles, ErrorsNameTheFile) {
    Image img(2, 2), out;
    EXPECT_NE(write_image(img, scratch("picture.jpg")).find("picture.jpg"), std::string::npos);
    EXPECT_NE(read_image("/nonexistent/dir/x.png", out).find("/nonexistent/dir/x.png"), std::string::npos);
    const std::string bogus = scratch("bogus.png");
    std::ofstream(bogus) << "this is not a png";
    const std::string e = read_image(bogus, out);
    EXPECT_NE(e.find("bogus.png"), std::string::npos) << e;
    const std::string bogus_ppm = scratch("bogus.ppm");
    std::ofstream(bogus_ppm) << "P3\n1 1\n255\n0 0 0\n";
    EXPECT_NE(read_image(bogus_ppm, out).find("P6"), std::string::npos);
    EXPECT_TRUE(has_image_extension("a/b.PpM"));
    EXPECT_FALSE(has_image_extension("a.png/b"));
}

TEST(ImageBytes, RoundsClampsAndZeroesNaN) {
    EXPECT_EQ(to_byte(0), 0);
    EXPECT_EQ(to_byte(-1), 0);
    EXPECT_EQ(to_byte(std::nan("")), 0);
    EXPECT_EQ(to_byte(1), 255);
    EXPECT_EQ(to_byte(7), 255);
    EXPECT_EQ(to_byte(0.5), 128);  // 127.5 rounds away from zero
    EXPECT_EQ(to_byte(1.0 / 255), 1);
}

TEST(ImageCompare, CountsPsnrAndDiffPicture) {
    const Image a = noise(10, 10, 1);
    Image b = a;
    EXPECT_TRUE(std::isinf(compare(a, b).psnr));
    EXPECT_EQ(compare(a, b).differing_pixels, 0);
    b.at(3, 4)[1] = std::uint8_t(b.at(3, 4)[1] ^ 0x80);  // one channel off by 128
    b.at(5, 5)[0] = std::uint8_t(b.at(5, 5)[0] == 255 ? 254 : b.at(5, 5)[0] + 1);  // off by 1
    const ImageComparison c = compare(a, b);
    EXPECT_EQ(c.differing_pixels, 2);
    EXPECT_EQ(c.max_channel_difference, 128);
    EXPECT_NEAR(c.psnr, 10 * std::log10(255.0 * 255 / ((128.0 * 128 + 1) / 300)), 1e-9);
    EXPECT_EQ(compare(a, b, 1).differing_pixels, 1);
    const Image d = diff_image(a, b);
    EXPECT_EQ(d.at(3, 4)[0], 255);
    EXPECT_EQ(d.at(3, 4)[1], 0);
    EXPECT_EQ(d.at(3, 4)[2], 255);
    EXPECT_LT(d.at(0, 0)[0], 100);  // the rest is dimmed grey
    EXPECT_EQ(d.at(0, 0)[0], d.at(0, 0)[2]);
    EXPECT_FALSE(compare(a, Image(10, 9)).same_size);
}

}  // namespace
}  // namespace rayproof::render::testing
