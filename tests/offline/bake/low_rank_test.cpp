// SPDX-License-Identifier: MIT
// Low-rank coefficient codes: exact for data of that rank, best for lower ranks (the error is
// the discarded variance), invalid texels coded as the mean, bad ranks refused.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "vpe/bake/low_rank_encoder.h"
#include "vpe/common/input_error.h"

namespace vpe::bake {
namespace {

// Texels on a `rank`-dimensional affine subspace of `channels`-space, plus optional noise.
std::vector<float> subspaceData(std::size_t texels, int channels, int rank, float noise) {
    std::mt19937 random(11);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    std::vector<float> axes(static_cast<std::size_t>(rank * channels));
    for (float& a : axes) {
        a = normal(random);
    }
    std::vector<float> data(texels * static_cast<std::size_t>(channels));
    for (std::size_t t = 0; t < texels; ++t) {
        std::vector<float> w(static_cast<std::size_t>(rank));
        for (int r = 0; r < rank; ++r) {
            w[static_cast<std::size_t>(r)] = normal(random) / static_cast<float>(r + 1);
        }
        for (int k = 0; k < channels; ++k) {
            float v = 0.3f + 0.01f * static_cast<float>(k);
            for (int r = 0; r < rank; ++r) {
                v += w[static_cast<std::size_t>(r)] *
                     axes[static_cast<std::size_t>(r * channels + k)];
            }
            data[t * static_cast<std::size_t>(channels) + static_cast<std::size_t>(k)] =
                v + noise * normal(random);
        }
    }
    return data;
}

double meanSquaredError(const std::vector<float>& a, const std::vector<float>& b) {
    double sum = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        sum += (static_cast<double>(a[i]) - b[i]) * (static_cast<double>(a[i]) - b[i]);
    }
    return sum / static_cast<double>(a.size());
}

TEST(LowRankCode, IsExactForDataOfThatRank) {
    const std::vector<float> data = subspaceData(3000, 66, 5, 0.0f);
    LowRankOptions options;
    options.rank = 5;
    options.threads = 2;
    const LowRankCode code = encodeLowRank(data, 66, {}, options);
    EXPECT_LT(meanSquaredError(decodeLowRank(code), data), 1e-9);
    double explained = 0;
    for (double e : code.explained) {
        explained += e;
    }
    EXPECT_NEAR(explained, 1.0, 1e-6);
    // Orthonormal basis rows.
    for (int a = 0; a < 5; ++a) {
        for (int b = 0; b < 5; ++b) {
            double dot = 0;
            for (int k = 0; k < 66; ++k) {
                dot += static_cast<double>(code.basis[static_cast<std::size_t>(a * 66 + k)]) *
                       code.basis[static_cast<std::size_t>(b * 66 + k)];
            }
            EXPECT_NEAR(dot, a == b ? 1.0 : 0.0, 1e-5);
        }
    }
}

TEST(LowRankCode, LowerRanksLoseWhatTheyDiscardAndNoMore) {
    const std::vector<float> data = subspaceData(4000, 30, 8, 0.0f);
    double previous = 1e30;
    double total = 0;
    {
        LowRankOptions full;
        full.rank = 30;
        const LowRankCode code = encodeLowRank(data, 30, {}, full);
        for (std::size_t t = 0; t < 4000; ++t) {
            for (int k = 0; k < 30; ++k) {
                const double d = static_cast<double>(data[t * 30 + static_cast<std::size_t>(k)]) -
                                 code.mean[static_cast<std::size_t>(k)];
                total += d * d;
            }
        }
        total /= 4000.0 * 30.0;
    }
    for (int rank = 1; rank <= 8; ++rank) {
        LowRankOptions options;
        options.rank = rank;
        const LowRankCode code = encodeLowRank(data, 30, {}, options);
        const double error = meanSquaredError(decodeLowRank(code), data);
        EXPECT_LT(error, previous) << "rank " << rank;
        double kept = 0;
        for (double e : code.explained) {
            kept += e;
        }
        // PCA's residual is exactly the discarded share of the variance.
        EXPECT_NEAR(error, (1.0 - kept) * total, 1e-4 * total + 1e-9) << "rank " << rank;
        previous = error;
    }
}

TEST(LowRankCode, InvalidTexelsAreLeftOutAndCodedAsTheMean) {
    std::vector<float> data = subspaceData(500, 6, 2, 0.0f);
    std::vector<unsigned char> valid(500, 1);
    for (std::size_t t = 0; t < 500; t += 7) {
        valid[t] = 0;
        for (int k = 0; k < 6; ++k) {
            data[t * 6 + static_cast<std::size_t>(k)] = 1e6f;  // garbage must not skew the basis
        }
    }
    LowRankOptions options;
    options.rank = 2;
    const LowRankCode code = encodeLowRank(data, 6, valid, options);
    const std::vector<float> decoded = decodeLowRank(code);
    for (std::size_t t = 0; t < 500; ++t) {
        for (int k = 0; k < 6; ++k) {
            const std::size_t i = t * 6 + static_cast<std::size_t>(k);
            if (valid[t]) {
                EXPECT_NEAR(decoded[i], data[i], 1e-4);
            } else {
                EXPECT_FLOAT_EQ(decoded[i], code.mean[static_cast<std::size_t>(k)]);
            }
        }
    }
}

TEST(LowRankCode, RefusesRanksOutsideTheChannels) {
    const std::vector<float> data(60, 1.0f);
    LowRankOptions options;
    options.rank = 0;
    EXPECT_THROW(encodeLowRank(data, 6, {}, options), common::InputError);
    options.rank = 7;
    EXPECT_THROW(encodeLowRank(data, 6, {}, options), common::InputError);
    options.rank = 2;
    EXPECT_THROW(encodeLowRank(data, 7, {}, options), common::InputError);  // 60 is not 7 × n
}

}  // namespace
}  // namespace vpe::bake
