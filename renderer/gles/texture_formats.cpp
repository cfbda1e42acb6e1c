// SPDX-License-Identifier: MIT
// Names of the sized internal formats the renderer allocates (see the header).
#include "texture_formats.h"

#include <stdexcept>

namespace vpe::renderer::gles {

std::string internalFormatName(GLenum internalFormat) {
    switch (internalFormat) {
        case GL_R8:
            return "R8";
        case GL_R16F:
            return "R16F";
        case GL_RG16F:
            return "RG16F";
        case GL_RG32F:
            return "RG32F";
        case GL_RG32UI:
            return "RG32UI";
        case GL_RGBA8:
            return "RGBA8";
        case GL_RGBA16F:
            return "RGBA16F";
        case GL_RGBA32F:
            return "RGBA32F";
        case GL_RGBA32UI:
            return "RGBA32UI";
        case GL_RGBA32I:
            return "RGBA32I";
        case GL_RGB10_A2:
            return "RGB10_A2";
        default:
            throw std::invalid_argument("internalFormatName: format 0x" +
                                        std::to_string(internalFormat) + " is not named here");
    }
}

}  // namespace vpe::renderer::gles
