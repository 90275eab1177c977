// ganzfeld-load: a load test of a running `ganzfeld serve` (docs/serve-load.md,
// driven by scripts/gen-serve-load-docs, smoke-tested by tests/serve_load_test.sh). CLIENTS
// threads, each with its own keep-alive httplib::Client, send REQUESTS requests each, a seeded mix:
//   eval      /api/eval of a few models and laws at random angles (tol 1e-6)
//   cached    /api/table of tables baked before the clock starts (warm-up, not timed)
//   uncached  /api/table of tables not in the cache when the clock starts; many clients ask for
//             each at once, so the service's single flight must bake each exactly once
// and prints one JSON document: throughput, latency quantiles (all and per kind), errors (any
// answer but 200, or no answer), and whether each uncached table was baked exactly once, judged
// twice: by the answers (X-Ganzfeld-Table: one "baked" per table, the others "joined" or
// "reused") and by the service's own counter (/healthz tables_baked, before and after).
// Every uncached table must find a bake slot: run the service with --jobs + --queue above
// kUncachedTables, or the refusals (503) are counted as errors.
// --slow-connections N keeps N slowloris connections open for the whole run: each sends a request
// head one byte every kSlowByteSeconds and never finishes it; one the service closes (its header
// deadline) is opened again, so that N are open throughout.
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <map>
#include <mutex>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "util/timing.h"

namespace {

using Json = nlohmann::ordered_json;

enum Kind { kEval, kCached, kUncached, kKinds };
constexpr std::array<const char*, kKinds> kKindNames{"eval", "cached", "uncached"};
/// Share of each kind in the mix, in percent (the rest is eval).
constexpr int kCachedPercent = 40, kUncachedPercent = 10;
constexpr int kCachedTables = 8, kUncachedTables = 12;

/// Table k of a set: small tables (a bake takes milliseconds to a second on 2 cores), so the test
/// measures the service, not the baker. Cached: Minnaert h in three formats; uncached: specular g.
std::string cached_target(int k) {
  static constexpr const char* kFormats[] = {"exr", "json", "ktx2"};
  return "/api/table?model=minnaert:xi=" + std::to_string(0.25 + 0.25 * k).substr(0, 4) +
         "&law=h&res=64&tol=1e-6&format=" + kFormats[k % 3];
}
std::string uncached_target(int k) {
  return "/api/table?model=specular:alpha=" + std::to_string(2 + k) + "&law=g&res=16x16x8&tol=1e-6";
}

std::string eval_target(std::mt19937_64& rng) {
  static constexpr const char* kModels[] = {"specular:alpha=8", "minnaert:xi=0.5", "lambert",
                                            "0.5*lambert%2B0.5*specular:alpha=4"};
  static constexpr const char* kLaws[] = {"f", "g", "h", "a"};
  std::uniform_real_distribution<double> angle(0.0, 80.0), azimuth(0.0, 180.0);
  std::uniform_int_distribution<int> model(0, 3), law(0, 3);
  return std::string("/api/eval?model=") + kModels[model(rng)] + "&law=" + kLaws[law(rng)] +
         "&theta_i=" + std::to_string(angle(rng)) + "&theta_j=" + std::to_string(angle(rng)) +
         "&phi=" + std::to_string(azimuth(rng)) + "&tol=1e-6";
}

struct Outcome {
  Kind kind;
  int table = -1;  ///< uncached table index
  double seconds = 0.0;
  int status = 0;  ///< 0: no answer
  std::string table_status, error;
};

struct Plan {
  Kind kind;
  int table;
  std::string target;
};

/// Seconds between two bytes of a slow connection's head.
constexpr double kSlowByteSeconds = 2.5;

/// N connections that send a request head one byte every kSlowByteSeconds, from one thread,
/// until stop(); a connection the service closes (its header deadline) is replaced.
class SlowConnections {
 public:
  SlowConnections(const std::string& host, int port, int count) : host_(host), port_(port) {
    for (int k = 0; k < count; ++k) sockets_.push_back(open());
    if (count > 0) thread_ = std::thread([this] { run(); });
  }
  ~SlowConnections() { stop(); }
  SlowConnections(const SlowConnections&) = delete;
  SlowConnections& operator=(const SlowConnections&) = delete;
  void stop() {
    stopping_ = true;
    if (thread_.joinable()) thread_.join();
    for (int fd : sockets_)
      if (fd >= 0) ::close(fd);
    sockets_.clear();
  }
  int opened() const { return opened_; }
  int open_now() const {
    int n = 0;
    for (int fd : sockets_) n += fd >= 0;
    return n;
  }

 private:
  int open() {
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(static_cast<std::uint16_t>(port_));
    inet_pton(AF_INET, host_ == "localhost" ? "127.0.0.1" : host_.c_str(), &address.sin_addr);
    if (fd < 0 || ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
      if (fd >= 0) ::close(fd);
      return -1;
    }
    static const std::string start = "GET /healthz HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ";
    if (::send(fd, start.data(), start.size(), MSG_NOSIGNAL) < 0) {
      ::close(fd);
      return -1;
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK);
    ++opened_;
    return fd;
  }
  void run() {
    using Clock = std::chrono::steady_clock;
    const auto step = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(kSlowByteSeconds));
    auto next = Clock::now() + step;
    while (!stopping_) {
      if (Clock::now() >= next) {
        next += step;
        for (int& fd : sockets_) {
          char answer[4096];
          const bool closed =
              fd < 0 || ::recv(fd, answer, sizeof answer, 0) >= 0 || ::send(fd, "a", 1, MSG_NOSIGNAL) < 0;
          if (closed) {  // answered (408) or closed by the service, or never connected: a new one
            if (fd >= 0) ::close(fd);
            fd = open();
          }
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  const std::string host_;
  const int port_;
  std::vector<int> sockets_;
  std::atomic<bool> stopping_{false};
  std::atomic<int> opened_{0};
  std::thread thread_;
};

std::vector<Plan> plan_of(int requests, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> percent(0, 99), cached(0, kCachedTables - 1), uncached(0, kUncachedTables - 1);
  std::vector<Plan> plan;
  for (int r = 0; r < requests; ++r) {
    const int p = percent(rng);
    if (p < kUncachedPercent) {
      const int k = uncached(rng);
      plan.push_back({kUncached, k, uncached_target(k)});
    } else if (p < kUncachedPercent + kCachedPercent) {
      plan.push_back({kCached, -1, cached_target(cached(rng))});
    } else {
      plan.push_back({kEval, -1, eval_target(rng)});
    }
  }
  return plan;
}

std::vector<Outcome> run_client(const std::string& host, int port, const std::vector<Plan>& plan) {
  httplib::Client client(host, port);
  client.set_keep_alive(true);
  client.set_read_timeout(120, 0);
  std::vector<Outcome> out;
  for (const Plan& p : plan) {
    Outcome o{p.kind, p.table, 0.0, 0, "", ""};
    const ganzfeld::util::Stopwatch watch;
    const httplib::Result res = client.Get(p.target.c_str());
    o.seconds = watch.seconds();
    if (!res) {
      o.error = "no answer: " + httplib::to_string(res.error());
    } else {
      o.status = res->status;
      o.table_status = res->get_header_value("X-Ganzfeld-Table");
      if (res->status != 200) o.error = std::to_string(res->status) + " " + res->body.substr(0, 200);
    }
    out.push_back(std::move(o));
  }
  return out;
}

Json health(httplib::Client& client) {
  const httplib::Result res = client.Get("/healthz");
  if (!res || res->status != 200) throw std::runtime_error("GET /healthz failed");
  return Json::parse(res->body);
}

Json latency(const std::vector<double>& seconds) {
  return {{"count", seconds.size()},
          {"p50_ms", 1e3 * ganzfeld::util::quantile(seconds, 0.50)},
          {"p99_ms", 1e3 * ganzfeld::util::quantile(seconds, 0.99)},
          {"max_ms", 1e3 * ganzfeld::util::quantile(seconds, 1.0)}};
}

Json report(const std::vector<Outcome>& all, double seconds, const Json& before, const Json& after) {
  std::vector<double> every;
  std::array<std::vector<double>, kKinds> by_kind;
  std::map<int, int> baked_answers;  ///< uncached table -> answers saying "baked"
  std::map<std::string, long long> statuses;
  long long errors = 0;
  Json samples = Json::array();
  for (const Outcome& o : all) {
    every.push_back(o.seconds);
    by_kind[o.kind].push_back(o.seconds);
    ++statuses[std::to_string(o.status)];
    if (o.kind == kUncached) baked_answers[o.table] += o.table_status == "baked";
    if (!o.error.empty() && ++errors <= 5) samples.push_back(o.error);
  }
  bool once = true;
  for (const auto& [table, baked] : baked_answers) once = once && baked == 1;
  const long long baked_by_server = after["tables_baked"].get<long long>() - before["tables_baked"].get<long long>();
  Json kinds;
  for (int k = 0; k < kKinds; ++k) kinds[kKindNames[k]] = latency(by_kind[k]);
  return {{"requests", all.size()},
          {"seconds", seconds},
          {"throughput_rps", static_cast<double>(all.size()) / seconds},
          {"latency", latency(every)},
          {"kinds", kinds},
          {"statuses", statuses},
          {"errors", errors},
          {"error_samples", samples},
          {"uncached_tables_requested", baked_answers.size()},
          {"tables_baked_by_server", baked_by_server},
          {"each_table_baked_once", once && baked_by_server == static_cast<long long>(baked_answers.size())},
          {"health_after", after}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"ganzfeld-load: load test of a running `ganzfeld serve` (one JSON document on stdout)"};
  std::string host = "127.0.0.1";
  int port = 0, clients = 16, requests = 2000, slow = 0;
  std::uint64_t seed = 1;
  app.add_option("--host", host, "the service's address (default 127.0.0.1; this machine only)");
  app.add_option("--port", port, "the service's port")->required()->check(CLI::Range(1, 65535));
  app.add_option("--clients", clients, "concurrent clients (default 16)")->check(CLI::Range(1, 256));
  app.add_option("--requests", requests, "requests per client (default 2000)")->check(CLI::Range(1, 1000000));
  app.add_option("--seed", seed, "seed of the request mix (default 1)");
  app.add_option("--slow-connections", slow, "slowloris connections kept open during the run (default 0)")
      ->check(CLI::Range(0, 1000));
  CLI11_PARSE(app, argc, argv);
  if (host != "127.0.0.1" && host != "localhost" && host != "::1") {
    std::fprintf(stderr, "ganzfeld-load: --host %s is not this machine; the load test targets loopback only\n",
                 host.c_str());
    return 2;
  }
  try {
    httplib::Client control(host, port);
    for (int k = 0; k < kCachedTables; ++k) {  // warm-up: the cached set, untimed
      const httplib::Result res = control.Get(cached_target(k).c_str());
      if (!res || res->status != 200) throw std::runtime_error("warm-up of " + cached_target(k) + " failed");
    }
    const Json before = health(control);
    SlowConnections slowloris(host, port, slow);
    if (slow > 0) std::this_thread::sleep_for(std::chrono::milliseconds(500));  // accepted before the clock starts
    std::vector<std::vector<Outcome>> outcomes(static_cast<std::size_t>(clients));
    std::vector<std::thread> threads;
    const ganzfeld::util::Stopwatch watch;
    for (int c = 0; c < clients; ++c)
      threads.emplace_back([&, c] {
        outcomes[static_cast<std::size_t>(c)] =
            run_client(host, port, plan_of(requests, seed * 1000003u + static_cast<std::uint64_t>(c)));
      });
    for (std::thread& t : threads) t.join();
    const double seconds = watch.seconds();
    const int slow_open_at_end = slowloris.open_now(), slow_opened = slowloris.opened();
    slowloris.stop();
    std::vector<Outcome> all;
    for (auto& o : outcomes) all.insert(all.end(), o.begin(), o.end());
    Json doc{{"clients", clients},
             {"requests_per_client", requests},
             {"seed", seed},
             {"slow_connections", slow},
             {"slow_connections_open_at_end", slow_open_at_end},
             {"slow_connections_opened", slow_opened}};
    doc.update(report(all, seconds, before, health(control)));
    std::printf("%s\n", doc.dump(2).c_str());
    return doc["errors"].get<long long>() == 0 && doc["each_table_baked_once"].get<bool>() ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ganzfeld-load: %s\n", e.what());
    return 1;
  }
}
