// SPDX-License-Identifier: MIT
// ProjectorResponse: gamma or sampled curve, and its clamped inverse.
#include "vpe/renderer/projector_response.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <string>

namespace vpe::renderer {

namespace {

const char* channelName(std::size_t c) {
    static const char* const kNames[] = {"red", "green", "blue"};
    return kNames[c];
}

}  // namespace

ProjectorResponse ProjectorResponse::gamma(double exponent) {
    return gamma({exponent, exponent, exponent});
}

ProjectorResponse ProjectorResponse::gamma(const std::array<double, 3>& exponents) {
    for (std::size_t c = 0; c < 3; ++c) {
        if (!(exponents[c] > 0) || !std::isfinite(exponents[c])) {
            throw std::invalid_argument(std::string("response: gamma of ") + channelName(c) +
                                        " must be a positive number");
        }
    }
    ProjectorResponse response;
    response.exponents_ = exponents;
    return response;
}

ProjectorResponse ProjectorResponse::sampled(std::vector<double> levels,
                                             std::array<std::vector<double>, 3> outputs) {
    return sampled(std::array<std::vector<double>, 3>{levels, levels, levels}, std::move(outputs));
}

ProjectorResponse ProjectorResponse::sampled(std::array<std::vector<double>, 3> levels,
                                             std::array<std::vector<double>, 3> outputs) {
    for (std::size_t c = 0; c < 3; ++c) {
        const std::string name = channelName(c);
        const auto& channelLevels = levels[c];
        auto& channel = outputs[c];
        if (channelLevels.size() < 2) {
            throw std::invalid_argument("response: " + name + " needs at least 2 samples");
        }
        if (channelLevels.front() != 0.0 || channelLevels.back() != 1.0) {
            throw std::invalid_argument("response: " + name + " levels must run from 0 to 1");
        }
        for (std::size_t k = 1; k < channelLevels.size(); ++k) {
            if (!(channelLevels[k] > channelLevels[k - 1])) {
                throw std::invalid_argument("response: " + name + " level " + std::to_string(k) +
                                            " is not above the one before");
            }
        }
        if (channel.size() != channelLevels.size()) {
            throw std::invalid_argument("response: " + name + " has " +
                                        std::to_string(channel.size()) + " outputs for " +
                                        std::to_string(channelLevels.size()) + " levels");
        }
        for (std::size_t k = 0; k < channel.size(); ++k) {
            if (!std::isfinite(channel[k]) || channel[k] < 0) {
                throw std::invalid_argument("response: " + name + " sample " + std::to_string(k) +
                                            " is not a finite value ≥ 0");
            }
            if (k > 0 && channel[k] < channel[k - 1]) {
                throw std::invalid_argument("response: " + name + " sample " + std::to_string(k) +
                                            " is below the one before");
            }
        }
        if (!(channel.back() > channel.front())) {
            throw std::invalid_argument("response: " + name + " does not rise");
        }
        const double full = channel.back();
        for (double& value : channel) {
            value /= full;
        }
        channel.back() = 1.0;  // exactly, whatever the division rounded to
    }
    ProjectorResponse response;
    response.levels_ = std::move(levels);
    response.outputs_ = std::move(outputs);
    return response;
}

double ProjectorResponse::output(int channel, double level) const {
    level = std::isnan(level) ? 0.0 : std::clamp(level, 0.0, 1.0);
    const auto c = static_cast<std::size_t>(channel);
    if (isGamma()) {
        return std::pow(level, exponents_[c]);
    }
    const auto& levels = levels_[c];
    const auto& outputs = outputs_[c];
    const auto upper = std::upper_bound(levels.begin(), levels.end(), level);
    if (upper == levels.end()) {
        return outputs.back();
    }
    const auto k = static_cast<std::size_t>(std::distance(levels.begin(), upper));  // ≥ 1
    const double f = (level - levels[k - 1]) / (levels[k] - levels[k - 1]);
    return outputs[k - 1] + f * (outputs[k] - outputs[k - 1]);
}

double ProjectorResponse::level(int channel, double fraction) const {
    if (std::isnan(fraction)) {
        return 0.0;
    }
    const auto c = static_cast<std::size_t>(channel);
    if (isGamma()) {
        return std::pow(std::clamp(fraction, 0.0, 1.0), 1.0 / exponents_[c]);
    }
    const auto& outputs = outputs_[c];
    if (fraction <= outputs.front()) {
        return 0.0;
    }
    // First sample at or above the fraction (for fraction ≥ 1: the first at full output, as
    // a curve may saturate before level 1); the one before is below it, so the segment between
    // them rises and the division is safe.
    const auto k = static_cast<std::size_t>(
        std::distance(outputs.begin(),
                      std::lower_bound(outputs.begin(), outputs.end(), std::min(fraction, 1.0))));
    const double f = (std::min(fraction, 1.0) - outputs[k - 1]) / (outputs[k] - outputs[k - 1]);
    const auto& levels = levels_[c];
    return std::clamp(levels[k - 1] + f * (levels[k] - levels[k - 1]), 0.0, 1.0);
}

}  // namespace vpe::renderer
