// SPDX-License-Identifier: MIT
// Shader compilation with named errors; GL object handles.
#include "gl_program.h"

#include <sstream>

#include <GLES3/gl31.h>

#include "vpe/renderer/gles/graphics_platform.h"

namespace vpe::renderer::gles {

std::string firstLine(const std::string& log) {
    std::size_t begin = log.find_first_not_of(" \t\r\n");
    if (begin == std::string::npos) {
        return "(no log)";
    }
    std::size_t end = log.find_first_of("\r\n", begin);
    std::string line =
        log.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
    while (!line.empty() && (line.back() == ' ' || line.back() == '\t')) {
        line.pop_back();
    }
    return line;
}

void checkGlError(std::string_view what) {
    const GLenum error = glGetError();
    if (error != GL_NO_ERROR) {
        std::ostringstream out;
        out << what << ": GL error 0x" << std::hex << error;
        throw GraphicsError(out.str());
    }
}

unsigned compileShader(unsigned stage, std::string_view name, const std::string& source) {
    // ES 3.1 is the device's limit (Pi 4/5 v3d); a desktop Mesa hands out 3.2 contexts for a
    // 3.1 request, so the shading language version is checked here, not left to the driver.
    const std::size_t begin = source.find_first_not_of(" \t\r\n");
    const std::string first = firstLine(source.substr(begin == std::string::npos ? 0 : begin));
    if (first != "#version 310 es" && first != "#version 300 es") {
        throw GraphicsError("shader '" + std::string(name) +
                            "' must start with '#version 310 es' " +
                            "(OpenGL ES 3.1 at most), not '" + first + "'");
    }
    const GLuint shader = glCreateShader(stage);
    if (shader == 0) {
        throw GraphicsError("shader '" + std::string(name) + "': glCreateShader failed");
    }
    const char* text = source.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        GLint length = 0;
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
        std::string log(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
        glGetShaderInfoLog(shader, static_cast<GLsizei>(log.size()), nullptr, log.data());
        glDeleteShader(shader);
        throw GraphicsError("shader '" + std::string(name) +
                            "' does not compile: " + firstLine(log.c_str()));
    }
    return shader;
}

unsigned linkProgram(std::string_view name, unsigned first, unsigned second) {
    const GLuint program = glCreateProgram();
    glAttachShader(program, first);
    if (second != 0) {
        glAttachShader(program, second);
    }
    glLinkProgram(program);
    glDeleteShader(first);
    if (second != 0) {
        glDeleteShader(second);
    }
    GLint ok = GL_FALSE;
    glGetProgramiv(program, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        GLint length = 0;
        glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
        std::string log(static_cast<std::size_t>(length > 0 ? length : 1), '\0');
        glGetProgramInfoLog(program, static_cast<GLsizei>(log.size()), nullptr, log.data());
        glDeleteProgram(program);
        throw GraphicsError("program '" + std::string(name) +
                            "' does not link: " + firstLine(log.c_str()));
    }
    return program;
}

void GlObject::reset() {
    if (name_ == 0) {
        return;
    }
    switch (kind_) {
        case Kind::kBuffer:
            glDeleteBuffers(1, &name_);
            break;
        case Kind::kTexture:
            glDeleteTextures(1, &name_);
            break;
        case Kind::kFramebuffer:
            glDeleteFramebuffers(1, &name_);
            break;
        case Kind::kRenderbuffer:
            glDeleteRenderbuffers(1, &name_);
            break;
        case Kind::kProgram:
            glDeleteProgram(name_);
            break;
        case Kind::kVertexArray:
            glDeleteVertexArrays(1, &name_);
            break;
    }
    name_ = 0;
}

GlObject GlObject::buffer() {
    GLuint name = 0;
    glGenBuffers(1, &name);
    return {Kind::kBuffer, name};
}
GlObject GlObject::texture() {
    GLuint name = 0;
    glGenTextures(1, &name);
    return {Kind::kTexture, name};
}
GlObject GlObject::framebuffer() {
    GLuint name = 0;
    glGenFramebuffers(1, &name);
    return {Kind::kFramebuffer, name};
}
GlObject GlObject::renderbuffer() {
    GLuint name = 0;
    glGenRenderbuffers(1, &name);
    return {Kind::kRenderbuffer, name};
}
GlObject GlObject::vertexArray() {
    GLuint name = 0;
    glGenVertexArrays(1, &name);
    return {Kind::kVertexArray, name};
}

namespace {

void setSampling(GLenum target, TextureFilter filter, TextureWrapS wrapS = TextureWrapS::kClamp) {
    const GLint mode = filter == TextureFilter::kLinear ? GL_LINEAR : GL_NEAREST;
    glTexParameteri(target, GL_TEXTURE_MIN_FILTER, mode);
    glTexParameteri(target, GL_TEXTURE_MAG_FILTER, mode);
    glTexParameteri(target, GL_TEXTURE_WRAP_S,
                    wrapS == TextureWrapS::kRepeat ? GL_REPEAT : GL_CLAMP_TO_EDGE);
    glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

}  // namespace

GlObject makeTexture2D(unsigned internalFormat, int width, int height, unsigned format,
                       unsigned type, const void* data, TextureFilter filter) {
    GlObject texture = GlObject::texture();
    glBindTexture(GL_TEXTURE_2D, texture.get());
    glTexStorage2D(GL_TEXTURE_2D, 1, static_cast<GLenum>(internalFormat), width, height);
    if (data != nullptr) {
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width, height, format, type, data);
    }
    setSampling(GL_TEXTURE_2D, filter);
    return texture;
}

GlObject makeArrayTexture(unsigned internalFormat, int width, int height, int layers,
                          unsigned format, unsigned type, const void* data, TextureFilter filter,
                          TextureWrapS wrapS) {
    GlObject texture = GlObject::texture();
    glBindTexture(GL_TEXTURE_2D_ARRAY, texture.get());
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, static_cast<GLenum>(internalFormat), width, height,
                   layers);
    if (data != nullptr) {
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, 0, width, height, layers, format, type, data);
    }
    setSampling(GL_TEXTURE_2D_ARRAY, filter, wrapS);
    return texture;
}

}  // namespace vpe::renderer::gles
