// SPDX-License-Identifier: MIT
// Compiling and linking GLSL ES programs with errors that name the shader, and the small RAII
// handles of GL objects the renderer owns.
#pragma once

#include <string>
#include <string_view>

namespace vpe::renderer::gles {

// Compiles one shader stage (GL_VERTEX_SHADER, GL_FRAGMENT_SHADER, GL_COMPUTE_SHADER). On
// failure throws GraphicsError "shader 'frame.frag' does not compile: 0:12(3): error: …" with
// the first line of the info log; a source that does not start with "#version 310 es" (or
// 300 es) is refused before the driver sees it: nothing beyond ES 3.1. Returns the shader name (the
// caller deletes it).
unsigned compileShader(unsigned stage, std::string_view name, const std::string& source);

// Links the stages into a program; the shaders are deleted. Throws GraphicsError naming the
// program and the log's first line.
unsigned linkProgram(std::string_view name, unsigned first, unsigned second = 0);

// The first line of a (possibly multi-line) log, trimmed; "(no log)" when empty.
std::string firstLine(const std::string& log);

// Throws GraphicsError "<what>: GL error 0x0501" if glGetError reports one.
void checkGlError(std::string_view what);

// An owned GL object name; deletes it with the function matching its kind.
class GlObject {
public:
    enum class Kind { kBuffer, kTexture, kFramebuffer, kRenderbuffer, kProgram, kVertexArray };
    GlObject() = default;
    GlObject(Kind kind, unsigned name) : kind_(kind), name_(name) {}
    ~GlObject() { reset(); }
    GlObject(GlObject&& other) noexcept : kind_(other.kind_), name_(other.name_) {
        other.name_ = 0;
    }
    GlObject& operator=(GlObject&& other) noexcept {
        if (this != &other) {
            reset();
            kind_ = other.kind_;
            name_ = other.name_;
            other.name_ = 0;
        }
        return *this;
    }
    GlObject(const GlObject&) = delete;
    GlObject& operator=(const GlObject&) = delete;
    unsigned get() const { return name_; }
    void reset();

    static GlObject buffer();
    static GlObject texture();
    static GlObject framebuffer();
    static GlObject renderbuffer();
    static GlObject vertexArray();
    static GlObject program(unsigned name) { return {Kind::kProgram, name}; }

private:
    Kind kind_ = Kind::kBuffer;
    unsigned name_ = 0;
};

enum class TextureFilter { kNearest, kLinear };
// Along s (x, the texture's u): clamp to edge, or repeat (a texture that tiles around the
// screen object). t always clamps.
enum class TextureWrapS { kClamp, kRepeat };

// An immutable 2D texture (one level, clamped to edge): internal format, then the data's
// format and type (GL enums); `data` may be null (storage only, filled later).
GlObject makeTexture2D(unsigned internalFormat, int width, int height, unsigned format,
                       unsigned type, const void* data,
                       TextureFilter filter = TextureFilter::kNearest);

// An immutable 2D texture array, likewise (a bundle's texture payloads: linear filtering),
// repeating along s if asked (a bundle whose textures wrap in u).
GlObject makeArrayTexture(unsigned internalFormat, int width, int height, int layers,
                          unsigned format, unsigned type, const void* data,
                          TextureFilter filter = TextureFilter::kLinear,
                          TextureWrapS wrapS = TextureWrapS::kClamp);

}  // namespace vpe::renderer::gles
