// Why a request's work stops before it is done (docs/serve.md, "Limits"): its deadline
// (--max-request-seconds) passed, its client went away, or the service is shutting down. The
// connection loop (serve/connection_loop.h) sets the flag; the engine reads it between panels
// (CubatureOptions::cancel) and the bakery between entries (tables::BakeCommon::cancel).
#pragma once

#include <atomic>
#include <string>

namespace ganzfeld::serve {

enum class StopReason { none, deadline, client_gone, shutdown };

class Cancellation {
 public:
  /// Sets the flag; the first reason given is the one kept.
  void cancel(StopReason why) noexcept {
    StopReason none = StopReason::none;
    reason_.compare_exchange_strong(none, why);
    flag_.store(true);
  }
  bool cancelled() const noexcept { return flag_.load(std::memory_order_relaxed); }
  StopReason reason() const noexcept { return reason_.load(); }
  /// The flag itself, for CubatureOptions::cancel and tables::BakeCommon::cancel.
  const std::atomic<bool>* flag() const noexcept { return &flag_; }

 private:
  std::atomic<bool> flag_{false};
  std::atomic<StopReason> reason_{StopReason::none};
};

/// One line for the error body of a request stopped for `why` after `budget_seconds` of budget.
inline std::string stop_message(StopReason why, double budget_seconds) {
  switch (why) {
    case StopReason::deadline:
      return "the request needed more than this service's limit of " +
             std::to_string(static_cast<long long>(budget_seconds)) +
             " s per request; ask for less (a looser tol, a smaller table) or run it with the command line";
    case StopReason::client_gone: return "the client closed the connection; the work was stopped";
    case StopReason::shutdown: return "the service is shutting down; retry later";
    case StopReason::none: break;
  }
  return "the request was stopped";
}

}  // namespace ganzfeld::serve
