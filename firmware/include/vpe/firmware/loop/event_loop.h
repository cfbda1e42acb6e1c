// SPDX-License-Identifier: MIT
// EventLoop: one epoll set over every file descriptor the player waits on (input lines, the
// camera's eventfd, the OSC socket, DRM page-flip events, the frame timer, signals, the bundle
// watch). The player sleeps in epoll_wait until one is ready: no busy waiting.
#pragma once

#include <csignal>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

namespace vpe::firmware {

class EventLoopError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class EventLoop {
public:
    EventLoop();
    ~EventLoop();
    EventLoop(const EventLoop&) = delete;
    EventLoop& operator=(const EventLoop&) = delete;

    // Calls `onReadable` whenever `fd` is readable (level-triggered) until unwatched. The
    // caller keeps the descriptor open for as long as it is watched.
    void watch(int fd, std::function<void()> onReadable);
    void unwatch(int fd);

    // Waits up to timeoutMs (−1: forever, 0: just look) and runs the handlers of the ready
    // descriptors, in the order epoll reports them. Returns how many ran. EINTR is not an
    // error (0 handlers).
    int runOnce(int timeoutMs);

private:
    int epoll_ = -1;
    std::map<int, std::shared_ptr<std::function<void()>>> handlers_;
};

// A periodic CLOCK_MONOTONIC timerfd: the headless frame clock, and the replay's scheduler.
class MonotonicTimer {
public:
    MonotonicTimer();
    ~MonotonicTimer();
    MonotonicTimer(const MonotonicTimer&) = delete;
    MonotonicTimer& operator=(const MonotonicTimer&) = delete;

    int fd() const { return fd_; }
    // Fires first at absolute monotonic `firstNs`, then every periodNs (0: once).
    void arm(std::int64_t firstNs, std::int64_t periodNs);
    void disarm();
    // Reads the expiry count (0 when none is pending); call when fd() is readable.
    std::uint64_t expirations();

private:
    int fd_ = -1;
};

// SIGHUP, SIGTERM, SIGINT through a signalfd: blocked for the process (set up before any
// thread starts, so that none of them receives the signals) and read in the loop.
class SignalWatch {
public:
    SignalWatch();
    ~SignalWatch();
    SignalWatch(const SignalWatch&) = delete;
    SignalWatch& operator=(const SignalWatch&) = delete;

    int fd() const { return fd_; }
    // The next pending signal number, 0 when none.
    int next();

private:
    int fd_ = -1;
    sigset_t previous_{};  // restored on destruction
};

}  // namespace vpe::firmware
