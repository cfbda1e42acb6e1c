// SPDX-License-Identifier: MIT
#include "failure_image.h"

#include <fstream>

#if VPE_TEST_PNG
#include <OpenImageIO/imageio.h>
#endif

namespace vpe::renderer::testing {

std::string writeFailureImage(const std::string& stem, int width, int height,
                              const std::vector<std::uint8_t>& rgb) {
#if VPE_TEST_PNG
    const std::string png = stem + ".png";
    auto image = OIIO::ImageOutput::create(png);
    const OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    if (image && image->open(png, spec)) {
        image->write_image(OIIO::TypeDesc::UINT8, rgb.data());
        image->close();
        return png;
    }
#endif
    const std::string ppm = stem + ".ppm";
    std::ofstream out(ppm, std::ios::binary);
    out << "P6\n" << width << " " << height << "\n255\n";
    out.write(reinterpret_cast<const char*>(rgb.data()), static_cast<std::streamsize>(rgb.size()));
    return ppm;
}

}  // namespace vpe::renderer::testing
