// SPDX-License-Identifier: MIT
// Texture formats: the declaration comments parsed line by line, and a table of texel sizes.
#include "texture_formats.h"

#include <regex>
#include <sstream>
#include <unordered_map>

namespace vpe::shader_cost {

std::optional<int> bytesPerTexel(const std::string& format) {
    // The sized internal formats of OpenGL ES 3.1 that a sampler can read.
    static const std::unordered_map<std::string, int> kTexelBytes = {
        {"R8", 1},
        {"R8_SNORM", 1},
        {"R8UI", 1},
        {"R8I", 1},
        {"RG8", 2},
        {"RG8_SNORM", 2},
        {"RG8UI", 2},
        {"RG8I", 2},
        {"RGB8", 3},
        {"SRGB8", 3},
        {"RGB8_SNORM", 3},
        {"RGB8UI", 3},
        {"RGB8I", 3},
        {"RGBA8", 4},
        {"SRGB8_ALPHA8", 4},
        {"RGBA8_SNORM", 4},
        {"RGBA8UI", 4},
        {"RGBA8I", 4},
        {"RGB565", 2},
        {"RGBA4", 2},
        {"RGB5_A1", 2},
        {"RGB10_A2", 4},
        {"RGB10_A2UI", 4},
        {"R11F_G11F_B10F", 4},
        {"RGB9_E5", 4},
        {"R16F", 2},
        {"R16UI", 2},
        {"R16I", 2},
        {"RG16F", 4},
        {"RG16UI", 4},
        {"RG16I", 4},
        {"RGB16F", 6},
        {"RGB16UI", 6},
        {"RGB16I", 6},
        {"RGBA16F", 8},
        {"RGBA16UI", 8},
        {"RGBA16I", 8},
        {"R32F", 4},
        {"R32UI", 4},
        {"R32I", 4},
        {"RG32F", 8},
        {"RG32UI", 8},
        {"RG32I", 8},
        {"RGB32F", 12},
        {"RGB32UI", 12},
        {"RGB32I", 12},
        {"RGBA32F", 16},
        {"RGBA32UI", 16},
        {"RGBA32I", 16},
        {"DEPTH_COMPONENT16", 2},
        {"DEPTH_COMPONENT24", 4},
        {"DEPTH_COMPONENT32F", 4},
        {"DEPTH24_STENCIL8", 4},
        {"DEPTH32F_STENCIL8", 8},
    };
    const auto found = kTexelBytes.find(format);
    return found == kTexelBytes.end() ? std::nullopt : std::optional<int>(found->second);
}

std::map<std::string, std::string> declaredTextureFormats(const std::string& source) {
    // [layout(...)] uniform [precision] SAMPLERTYPE NAME; // [format:] FORMAT ...
    static const std::regex kDeclaration(
        R"(^\s*(?:layout\s*\([^)]*\)\s*)?uniform\s+(?:\w+\s+)*\w*sampler\w*\s+(\w+)\s*;\s*//\s*(?:format:\s*)?([A-Za-z0-9_]+))");
    std::map<std::string, std::string> formats;
    std::istringstream lines(source);
    std::string line;
    while (std::getline(lines, line)) {
        std::smatch match;
        if (std::regex_search(line, match, kDeclaration) && bytesPerTexel(match[2].str())) {
            formats[match[1].str()] = match[2].str();
        }
    }
    return formats;
}

std::set<std::string> declaredCachedTextures(const std::string& source) {
    static const std::regex kDeclaration(
        R"(^\s*(?:layout\s*\([^)]*\)\s*)?uniform\s+(?:\w+\s+)*\w*sampler\w*\s+(\w+)\s*;\s*//\s*(?:format:\s*)?([A-Za-z0-9_]+)\s+cached\b)");
    std::set<std::string> cached;
    std::istringstream lines(source);
    std::string line;
    while (std::getline(lines, line)) {
        std::smatch match;
        if (std::regex_search(line, match, kDeclaration) && bytesPerTexel(match[2].str())) {
            cached.insert(match[1].str());
        }
    }
    return cached;
}

std::int64_t declaredOutputBytes(const std::string& source) {
    // [layout(...)] out [precision] TYPE NAME; // [format:] FORMAT ...
    static const std::regex kDeclaration(
        R"(^\s*(?:layout\s*\([^)]*\)\s*)?out\s+(?:\w+\s+)*\w+\s+\w+\s*;\s*//\s*(?:format:\s*)?([A-Za-z0-9_]+))");
    std::int64_t bytes = 0;
    std::istringstream lines(source);
    std::string line;
    while (std::getline(lines, line)) {
        std::smatch match;
        if (std::regex_search(line, match, kDeclaration)) {
            if (const std::optional<int> texel = bytesPerTexel(match[1].str())) {
                bytes += *texel;
            }
        }
    }
    return bytes;
}

}  // namespace vpe::shader_cost
