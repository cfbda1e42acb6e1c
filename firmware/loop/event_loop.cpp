// SPDX-License-Identifier: MIT
#include "vpe/firmware/loop/event_loop.h"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <vector>

#include <sys/epoll.h>
#include <sys/signalfd.h>
#include <sys/timerfd.h>
#include <unistd.h>

namespace vpe::firmware {

namespace {

[[noreturn]] void failWith(const std::string& what) {
    throw EventLoopError(what + ": " + std::strerror(errno));
}

}  // namespace

EventLoop::EventLoop() : epoll_(::epoll_create1(EPOLL_CLOEXEC)) {
    if (epoll_ < 0) {
        failWith("event loop: epoll_create1");
    }
}

EventLoop::~EventLoop() {
    ::close(epoll_);
}

void EventLoop::watch(int fd, std::function<void()> onReadable) {
    epoll_event event{};
    event.events = EPOLLIN;
    event.data.fd = fd;
    const bool known = handlers_.contains(fd);
    if (::epoll_ctl(epoll_, known ? EPOLL_CTL_MOD : EPOLL_CTL_ADD, fd, &event) != 0) {
        failWith("event loop: cannot watch descriptor " + std::to_string(fd));
    }
    handlers_[fd] = std::make_shared<std::function<void()>>(std::move(onReadable));
}

void EventLoop::unwatch(int fd) {
    if (handlers_.erase(fd) > 0) {
        ::epoll_ctl(epoll_, EPOLL_CTL_DEL, fd, nullptr);
    }
}

int EventLoop::runOnce(int timeoutMs) {
    epoll_event events[32];
    const int ready = ::epoll_wait(epoll_, events, 32, timeoutMs);
    if (ready < 0) {
        if (errno == EINTR) {
            return 0;
        }
        failWith("event loop: epoll_wait");
    }
    int ran = 0;
    for (int i = 0; i < ready; ++i) {
        // A handler may unwatch another descriptor of this batch: look each one up again,
        // and keep the handler alive while it runs (it may unwatch itself).
        const auto found = handlers_.find(events[i].data.fd);
        if (found == handlers_.end()) {
            continue;
        }
        const std::shared_ptr<std::function<void()>> handler = found->second;
        (*handler)();
        ++ran;
    }
    return ran;
}

MonotonicTimer::MonotonicTimer()
    : fd_(::timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC)) {
    if (fd_ < 0) {
        failWith("timer: timerfd_create");
    }
}

MonotonicTimer::~MonotonicTimer() {
    ::close(fd_);
}

void MonotonicTimer::arm(std::int64_t firstNs, std::int64_t periodNs) {
    itimerspec spec{};
    // it_value 0 would disarm: a first expiry in the past fires at once from 1 ns.
    const std::int64_t first = firstNs > 0 ? firstNs : 1;
    spec.it_value.tv_sec = static_cast<time_t>(first / 1'000'000'000);
    spec.it_value.tv_nsec = static_cast<long>(first % 1'000'000'000);
    spec.it_interval.tv_sec = static_cast<time_t>(periodNs / 1'000'000'000);
    spec.it_interval.tv_nsec = static_cast<long>(periodNs % 1'000'000'000);
    if (::timerfd_settime(fd_, TFD_TIMER_ABSTIME, &spec, nullptr) != 0) {
        failWith("timer: timerfd_settime");
    }
}

void MonotonicTimer::disarm() {
    itimerspec spec{};
    ::timerfd_settime(fd_, 0, &spec, nullptr);
}

std::uint64_t MonotonicTimer::expirations() {
    std::uint64_t count = 0;
    if (::read(fd_, &count, sizeof count) != static_cast<ssize_t>(sizeof count)) {
        return 0;  // EAGAIN: nothing pending (a re-arm raced the read)
    }
    return count;
}

SignalWatch::SignalWatch() {
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGHUP);
    sigaddset(&signals, SIGTERM);
    sigaddset(&signals, SIGINT);
    if (::sigprocmask(SIG_BLOCK, &signals, &previous_) != 0) {
        failWith("signals: sigprocmask");
    }
    fd_ = ::signalfd(-1, &signals, SFD_NONBLOCK | SFD_CLOEXEC);
    if (fd_ < 0) {
        failWith("signals: signalfd");
    }
}

SignalWatch::~SignalWatch() {
    ::close(fd_);
    ::sigprocmask(SIG_SETMASK, &previous_, nullptr);
}

int SignalWatch::next() {
    signalfd_siginfo info{};
    if (::read(fd_, &info, sizeof info) != static_cast<ssize_t>(sizeof info)) {
        return 0;
    }
    return static_cast<int>(info.ssi_signo);
}

}  // namespace vpe::firmware
