// SPDX-License-Identifier: MIT
// Classic RTI baselines (PTM-6, PTM-10, HSH-9, HSH-16) on SynthRTI, fitted on Dome/ and scored
// on Test/ with `vpe eval`'s metric, so vpe's numbers compare with them on the same footing.
// The bases are `vpe fit --model`'s (one set at a time: vpe fit Dome --model hsh16, vpe eval
// Test); this tool runs all the sets at once and also fits them in linear radiance.
//   vpe_rti_baselines [--sets PATTERN]... [--json FILE] [--threads N]
// PATTERN is a glob (fnmatch) matched against a set's name or any leading part of it:
// "Single/Object1" selects that object's materials, "*/Object2/material3" one per group.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <fnmatch.h>
#include <nlohmann/json.hpp>

#include "vpe/capture/capture_loader.h"
#include "vpe/capture/image_band_reader.h"
#include "vpe/common/parallel_for.h"
#include "vpe/eval/model_evaluation.h"
#include "vpe/model/rti_basis.h"
#include "vpe/proto/srgb.h"

#include "support/test_data.h"

namespace vpe {
namespace {

// The bases as `vpe fit --model ptm6|ptm10|hsh9|hsh16` fits them (model/rti_basis.h).
const std::array<model::RtiBasis, 4> kBases{
    *model::RtiBasis::parse("ptm6"), *model::RtiBasis::parse("ptm10"),
    *model::RtiBasis::parse("hsh9"), *model::RtiBasis::parse("hsh16")};
constexpr std::array<const char*, 4> kBasisNames{"PTM-6", "PTM-10", "HSH-9", "HSH-16"};

// The domain the coefficients are fitted in. RTI tools fit the 8-bit codes (code/255);
// vpe fits linear radiance.
enum class Domain { kSrgb, kLinear };
constexpr std::array<Domain, 2> kDomains{Domain::kSrgb, Domain::kLinear};
constexpr std::array<const char*, 2> kDomainNames{"srgb", "linear"};

Eigen::MatrixXd designMatrix(const model::RtiBasis& basis, const capture::Capture& capture) {
    Eigen::MatrixXd a(static_cast<Eigen::Index>(capture.images.size()), basis.terms);
    std::vector<double> row(static_cast<std::size_t>(basis.terms));
    for (std::size_t i = 0; i < capture.images.size(); ++i) {
        basis.evaluate(capture.images[i].light, row.data());
        for (int j = 0; j < basis.terms; ++j) {
            a(static_cast<Eigen::Index>(i), j) = row[static_cast<std::size_t>(j)];
        }
    }
    return a;
}

// The whole prediction is linear in the observations and the design is the same for every
// pixel: Test values = B (AᵀA + λI)⁻¹ Aᵀ · Dome values, one Nt × Nd matrix per set and basis.
Eigen::MatrixXd predictionOperator(const model::RtiBasis& basis, const capture::Capture& dome,
                                   const capture::Capture& test) {
    const Eigen::MatrixXd a = designMatrix(basis, dome);
    Eigen::MatrixXd gram = a.transpose() * a;
    // A tiny ridge only guards against round-off; it does not regularize the fit.
    gram.diagonal().array() += 1e-6 * gram.trace();
    return designMatrix(basis, test) * gram.ldlt().solve(a.transpose());
}

// A capture decoded whole, as rows = images and columns = (pixel, channel), in linear
// radiance exactly as `vpe eval` reads it.
struct DecodedCapture {
    int width = 0;
    int height = 0;
    Eigen::MatrixXd linear;
};

DecodedCapture decode(const capture::Capture& capture, unsigned threads) {
    capture::ImageBandReader reader(capture, threads);
    capture::SampleBand band;
    reader.readBand(0, reader.height(), nullptr, band);
    DecodedCapture out;
    out.width = reader.width();
    out.height = reader.height();
    const Eigen::Index columns = static_cast<Eigen::Index>(out.width) * out.height * 3;
    out.linear.resize(reader.imageCount(), columns);
    common::parallelFor(
        static_cast<std::size_t>(out.height), 1, threads, [&](std::size_t begin, std::size_t end) {
            for (std::size_t r = begin; r < end; ++r) {
                const int y = static_cast<int>(r);
                for (int x = 0; x < out.width; ++x) {
                    const Eigen::Index column = (static_cast<Eigen::Index>(y) * out.width + x) * 3;
                    for (int s = 0; s < reader.imageCount(); ++s) {
                        for (int c = 0; c < 3; ++c) {
                            out.linear(s, column + c) = band.value(s, c, y, x);
                        }
                    }
                }
            }
        });
    return out;
}

struct SetResult {
    std::string name;
    // [domain][basis] → per-Test-image PSNR and their mean
    std::array<std::array<std::vector<double>, 4>, 2> imagePsnr;
    std::array<std::array<double, 4>, 2> psnr{};
};

SetResult evaluateSet(const std::filesystem::path& dir, const std::string& name, unsigned threads) {
    const capture::Capture dome = capture::openCapture(dir / "Dome");
    const capture::Capture test = capture::openCapture(dir / "Test");
    const DecodedCapture domeImages = decode(dome, threads);
    const DecodedCapture testImages = decode(test, threads);
    if (domeImages.width != testImages.width || domeImages.height != testImages.height) {
        throw std::runtime_error(name + ": Dome and Test images differ in size");
    }
    const Eigen::Index columns = testImages.linear.cols();
    const Eigen::Index testCount = testImages.linear.rows();
    std::array<Eigen::MatrixXd, kBases.size()> operators;
    for (std::size_t b = 0; b < kBases.size(); ++b) {
        operators[b] = predictionOperator(kBases[b], dome, test);
    }

    // Column blocks in parallel, every per-value step inside them. Each block's squared
    // errors are kept apart and summed in block order, so the result does not depend on the
    // thread count.
    constexpr Eigen::Index kBlock = 4096;
    using Errors = std::array<std::array<Eigen::VectorXd, kBases.size()>, kDomains.size()>;
    const std::size_t blocks = static_cast<std::size_t>((columns + kBlock - 1) / kBlock);
    std::vector<Errors> blockErrors(blocks);
    common::parallelFor(blocks, 1, threads, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
            const Eigen::Index first = static_cast<Eigen::Index>(k) * kBlock;
            const Eigen::Index width = std::min(kBlock, columns - first);
            // The truth, as `vpe eval` encodes it.
            const Eigen::MatrixXd truth =
                testImages.linear.middleCols(first, width).unaryExpr([](double v) {
                    return proto::linearToSrgb(std::clamp(v, 0.0, 1.0));
                });
            for (std::size_t d = 0; d < kDomains.size(); ++d) {
                const Domain domain = kDomains[d];
                // linearToSrgb of a decoded 8-bit value gives back code/255 to float
                // precision.
                const Eigen::MatrixXd observations =
                    domain == Domain::kLinear
                        ? Eigen::MatrixXd(domeImages.linear.middleCols(first, width))
                        : Eigen::MatrixXd(
                              domeImages.linear.middleCols(first, width).unaryExpr([](double v) {
                                  return proto::linearToSrgb(v);
                              }));
                for (std::size_t b = 0; b < kBases.size(); ++b) {
                    const Eigen::MatrixXd predicted = operators[b] * observations;
                    Eigen::VectorXd error = Eigen::VectorXd::Zero(testCount);
                    for (Eigen::Index col = 0; col < width; ++col) {
                        for (Eigen::Index s = 0; s < testCount; ++s) {
                            const double p = std::clamp(predicted(s, col), 0.0, 1.0);
                            const double p8 =
                                domain == Domain::kLinear ? proto::linearToSrgb(p) : p;
                            const double diff = p8 - truth(s, col);
                            error(s) += diff * diff;
                        }
                    }
                    blockErrors[k][d][b] = std::move(error);
                }
            }
        }
    });

    SetResult result;
    result.name = name;
    for (std::size_t d = 0; d < kDomains.size(); ++d) {
        for (std::size_t b = 0; b < kBases.size(); ++b) {
            Eigen::VectorXd squaredError = Eigen::VectorXd::Zero(testCount);
            for (const Errors& errors : blockErrors) {
                squaredError += errors[d][b];
            }
            double sum = 0;
            for (Eigen::Index s = 0; s < testCount; ++s) {
                const double psnr =
                    eval::psnrFromMse(squaredError(s) / static_cast<double>(columns));
                result.imagePsnr[d][b].push_back(psnr);
                sum += psnr;
            }
            result.psnr[d][b] = sum / static_cast<double>(testCount);
        }
    }
    return result;
}

// A set is selected when the pattern matches its name or a leading run of its components.
bool selected(const std::string& name, const std::vector<std::string>& patterns) {
    if (patterns.empty()) {
        return true;
    }
    for (const std::string& pattern : patterns) {
        for (std::size_t end = name.find('/');; end = name.find('/', end + 1)) {
            const std::string prefix = name.substr(0, end);
            if (fnmatch(pattern.c_str(), prefix.c_str(), FNM_PATHNAME) == 0) {
                return true;
            }
            if (end == std::string::npos) {
                break;
            }
        }
    }
    return false;
}

// Group/Object*/material* folders holding Dome/ and Test/.
std::vector<std::string> findSets(const std::filesystem::path& root) {
    std::vector<std::string> sets;
    for (const char* group : {"Single", "Multi"}) {
        std::error_code error;
        if (!std::filesystem::is_directory(root / group, error)) {
            continue;
        }
        std::vector<std::string> inGroup;
        for (const auto& object : std::filesystem::directory_iterator(root / group)) {
            if (!object.is_directory()) {
                continue;
            }
            for (const auto& material : std::filesystem::directory_iterator(object.path())) {
                if (std::filesystem::is_directory(material.path() / "Dome") &&
                    std::filesystem::is_directory(material.path() / "Test")) {
                    inGroup.push_back(std::string(group) + "/" + object.path().filename().string() +
                                      "/" + material.path().filename().string());
                }
            }
        }
        std::sort(inGroup.begin(), inGroup.end());
        sets.insert(sets.end(), inGroup.begin(), inGroup.end());
    }
    return sets;
}

void printRow(const std::string& label, const std::array<std::array<double, 4>, 2>& psnr) {
    std::printf("%-28s", label.c_str());
    for (std::size_t d = 0; d < kDomains.size(); ++d) {
        std::printf(" ");
        for (std::size_t b = 0; b < kBases.size(); ++b) {
            std::printf(" %7.2f", psnr[d][b]);
        }
    }
    std::printf("\n");
}

int usage(const char* program) {
    std::fprintf(stderr, "usage: %s [--sets PATTERN]... [--json FILE] [--threads N]\n", program);
    return 2;
}

int run(int argc, char** argv) {
    std::vector<std::string> patterns;
    std::optional<std::filesystem::path> jsonPath;
    int threadRequest = 0;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--help" || arg == "-h") {
            usage(argv[0]);
            return 0;
        }
        if (i + 1 >= argc) {
            return usage(argv[0]);
        }
        if (arg == "--sets") {
            patterns.push_back(argv[++i]);
        } else if (arg == "--json") {
            jsonPath = argv[++i];
        } else if (arg == "--threads") {
            threadRequest = std::atoi(argv[++i]);
        } else {
            return usage(argv[0]);
        }
    }
    const auto dataDir = testing::realDataDir();
    const std::filesystem::path root = dataDir ? *dataDir / "synthrti" : "";
    std::error_code error;
    if (!dataDir || !std::filesystem::is_directory(root, error)) {
        std::printf("SynthRTI not found: set VPE_DATA or provide ../shared/data/synthrti\n");
        return 0;
    }
    std::vector<std::string> sets = findSets(root);
    std::erase_if(sets, [&](const std::string& name) { return !selected(name, patterns); });
    if (sets.empty()) {
        std::fprintf(stderr, "no set under %s matches\n", root.c_str());
        return 2;
    }
    const unsigned threads = common::resolveThreadCount(threadRequest);
    const auto start = std::chrono::steady_clock::now();

    std::printf("SynthRTI %s: fit on Dome, PSNR (dB) on Test, mean over images\n", root.c_str());
    std::printf("%-28s  %-31s  %-31s\n", "", "fitted in sRGB (code/255)", "fitted in linear");
    std::printf("%-28s", "set");
    for (std::size_t d = 0; d < kDomains.size(); ++d) {
        std::printf(" ");
        for (const char* basis : kBasisNames) {
            std::printf(" %7s", basis);
        }
    }
    std::printf("\n");

    std::vector<SetResult> results;
    for (const std::string& name : sets) {
        results.push_back(evaluateSet(root / name, name, threads));
        printRow(name, results.back().psnr);
        std::fflush(stdout);
    }

    // Means over sets, per group and overall.
    std::map<std::string, std::pair<std::array<std::array<double, 4>, 2>, int>> means;
    for (const SetResult& result : results) {
        const std::string group = result.name.substr(0, result.name.find('/'));
        for (const std::string& key : {group, std::string("All")}) {
            auto& [sum, count] = means[key];
            for (std::size_t d = 0; d < kDomains.size(); ++d) {
                for (std::size_t b = 0; b < kBases.size(); ++b) {
                    sum[d][b] += result.psnr[d][b];
                }
            }
            ++count;
        }
    }
    for (auto& [key, entry] : means) {
        for (auto& domain : entry.first) {
            for (double& value : domain) {
                value /= entry.second;
            }
        }
    }
    std::printf("\n");
    for (const char* key : {"Single", "Multi", "All"}) {
        if (const auto it = means.find(key); it != means.end()) {
            printRow("mean " + it->first + " (" + std::to_string(it->second.second) + " sets)",
                     it->second.first);
        }
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("\n%zu sets in %.1f s on %u threads\n", results.size(), seconds, threads);

    if (jsonPath) {
        auto byBasis = [](const auto& values) {
            nlohmann::json json;
            for (std::size_t d = 0; d < kDomains.size(); ++d) {
                for (std::size_t b = 0; b < kBases.size(); ++b) {
                    json[kDomainNames[d]][kBasisNames[b]] = values[d][b];
                }
            }
            return json;
        };
        nlohmann::json json;
        json["data"] = root.string();
        json["metric"] =
            "Test images: prediction clamped to [0,1] (in the fitting domain), sRGB-encoded, "
            "vs sRGB truth; PSNR = 10 log10(1/MSE) per image, mean over images";
        json["sets"] = nlohmann::json::array();
        for (const SetResult& result : results) {
            json["sets"].push_back({{"name", result.name},
                                    {"psnr", byBasis(result.psnr)},
                                    {"image_psnr", byBasis(result.imagePsnr)}});
        }
        for (const auto& [key, entry] : means) {
            json["means"][key] = {{"sets", entry.second}, {"psnr", byBasis(entry.first)}};
        }
        json["seconds"] = seconds;
        std::ofstream out(*jsonPath);
        out << json.dump(2) << "\n";
        if (!out) {
            std::fprintf(stderr, "cannot write %s\n", jsonPath->c_str());
            return 1;
        }
    }
    return 0;
}

}  // namespace
}  // namespace vpe

int main(int argc, char** argv) {
    try {
        return vpe::run(argc, argv);
    } catch (const std::exception& error) {
        std::fprintf(stderr, "vpe_rti_baselines: %s\n", error.what());
        return 1;
    }
}
