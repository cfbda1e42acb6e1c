// SPDX-License-Identifier: MIT
// What the accuracy-curve benchmarks (vpe_compression_curve, vpe_theta_basis_curve) share: the
// texture they bake — a vpe quilt folder with one preset, or a model file — and the scratch
// folder their bundles go to.
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "vpe/bake/scene_baker.h"

namespace vpe::benchmarks {

struct CurveArguments {
    bake::BakeOptions options;  // the texture, the preset and vpe bake's default viewer
    bool json = false;
};

// (--quilt DIR --preset WEIGHTS | --texture MODEL.exr) [--json]; prints the usage line and
// returns nothing when the arguments are not that.
std::optional<CurveArguments> parseCurveArguments(int argc, char** argv);

// A fresh folder in the temporary directory, removed with everything in it on destruction.
class CurveWorkFolder {
public:
    explicit CurveWorkFolder(const std::string& prefix);
    ~CurveWorkFolder();
    CurveWorkFolder(const CurveWorkFolder&) = delete;
    CurveWorkFolder& operator=(const CurveWorkFolder&) = delete;
    std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

private:
    std::filesystem::path path_;
};

// A curve program's main: the arguments (exit status 2 with the usage line when they are not
// that), a work folder named from `workPrefix`, then `curve`; an exception it throws is one line
// on stderr and exit status 2.
using Curve = std::function<void(const CurveArguments&, const CurveWorkFolder&)>;
int runCurve(int argc, char** argv, const std::string& workPrefix, const Curve& curve);

}  // namespace vpe::benchmarks
