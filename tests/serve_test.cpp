// The service without HTTP (serve/): request validation and its one-line errors, the query
// decoder, ETags, single-flight bakes on a bounded queue, and whole requests through
// Service::handle against a temporary cache. tests/serve_test.sh runs the real server.
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <latch>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "serve/bakery.h"
#include "serve/etag.h"
#include "serve/http.h"
#include "serve/request.h"
#include "serve/request_head.h"
#include "serve/service.h"
#include "tests/temp_dir.h"
#include "util/error.h"

namespace ganzfeld::serve {
namespace {

/// How long a fake bake holds its job slot: long enough that every thread of a test has
/// submitted before it ends (the threads start together on a latch).
constexpr auto kFakeBake = std::chrono::milliseconds(300);

/// The status and message of the RequestError that `f` throws (0 and "" if none).
template <class F>
std::pair<int, std::string> refusal(F&& f) {
  try {
    f();
  } catch (const RequestError& e) { return {e.status(), e.what()}; }
  return {0, ""};
}

std::pair<int, std::string> eval_refusal(const std::string& query) {
  return refusal([&] { parse_eval(parse_query(query), Limits{}); });
}
/// Each query of /api/eval is refused with 400 in one line that contains its fragment.
void expect_eval_refusals(const std::vector<std::pair<std::string, std::string>>& cases) {
  for (const auto& [query, fragment] : cases) {
    const auto [status, message] = eval_refusal(query);
    EXPECT_EQ(status, 400) << query;
    EXPECT_NE(message.find(fragment), std::string::npos) << query << " -> " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
  }
}
std::pair<int, std::string> table_refusal(const std::string& query) {
  return refusal([&] { parse_table(parse_query(query), Limits{}, TableEndpoint::table); });
}

TEST(ServeQuery, SplitsAtTheFirstEqualsAndDecodes) {
  const Query q = parse_query("model=specular:alpha=8&law=g&x=a%2Bb+c&empty=&flag");
  EXPECT_EQ(q.find("model")->second, "specular:alpha=8");
  EXPECT_EQ(q.find("x")->second, "a+b c");
  EXPECT_EQ(q.find("empty")->second, "");
  EXPECT_EQ(q.count("flag"), 1u);
  EXPECT_EQ(parse_query("").size(), 0u);
  EXPECT_EQ(refusal([] { parse_query("model=%zz"); }).first, 400);
  EXPECT_EQ(refusal([] { parse_query("model=%4"); }).first, 400);
}

TEST(ServeRequest, EvalAcceptsAnglesToleranceAndASkyBelowTheHorizon) {
  const EvalQuery q =
      parse_eval(parse_query("model=specular:alpha=8&law=g&theta_i=120&theta_j=30&phi=180&tol=1e-8"), Limits{});
  EXPECT_EQ(q.law, Law::g);
  EXPECT_EQ(q.model->spec(), "specular:alpha=8");
  ASSERT_TRUE(q.i && q.j);
  EXPECT_NEAR(q.i->z, -0.5, 1e-15);  // cos 120°: the sky pole below the horizon, allowed for g
  EXPECT_EQ(q.options.abs_tol, 1e-8);
  const EvalQuery h = parse_eval(parse_query("model=lambert&law=h&theta_j=10"), Limits{});
  EXPECT_FALSE(h.i);  // h does not use i
  EXPECT_TRUE(h.j);
}

TEST(ServeRequest, EvalRefusalsNameTheBadValue) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"model=no-such&law=h&theta_j=1", "unknown model 'no-such'"},
      {"model=specular:alpha=0&law=h&theta_j=1", "alpha"},
      {"model=lambert&law=x&theta_j=1", "unknown law 'x'"},
      {"model=lambert&law=h&theta_j=95", "theta_j=95 is out of range; allowed: [0, 90]"},
      {"model=lambert&law=a&theta_i=100", "theta_i=100 is out of range; allowed: [0, 90]"},
      {"model=lambert&law=g&theta_i=181&theta_j=0", "theta_i=181 is out of range; allowed: [0, 180]"},
      {"model=lambert&law=h&theta_j=abc", "theta_j='abc' is not a number"},
      {"model=lambert&law=h&theta_j=nan", "theta_j='nan' is not a number"},
      {"model=lambert&law=h", "missing parameter 'theta_j'"},
      {"law=h&theta_j=1", "missing parameter 'model'"},
      {"model=lambert&law=h&theta_j=1&tol=0", "tol=0 is not allowed"},
      {"model=lambert&law=h&theta_j=1&bogus=1", "unknown parameter 'bogus' for /api/eval; allowed: model, law"},
      {"model=lambert&law=h&theta_j=1&theta_j=2", "'theta_j' is given more than once"},
      {"model=merl:file=/etc/passwd&law=h&theta_j=1", "names a data file"},
      {"model=0.5*lambert %2B 0.5*tabulated: file = ../x&law=h&theta_j=1", "names a data file"},
  };
  expect_eval_refusals(cases);
}

// Numbers as documented (docs/serve.md): finite decimal numbers only; phi within a turn; the
// mixture weights' sum finite (it was NaN: "-nan*lambert + -nan*lambert"); lobes capped.
TEST(ServeRequest, NumbersAreFiniteDecimalsAndMixturesAreBounded) {
  for (const std::string text : {"0x1p3", "0x10", "inf", "-infinity", "1e999", " 5", "+5", "5 ", "1,5", "4e", ""}) {
    const auto [status, message] = eval_refusal("model=lambert&law=h&theta_j=" + text);
    EXPECT_EQ(status, 400) << "theta_j='" << text << "'";
    if (!text.empty()) {
      EXPECT_NE(message.find("is not a number; expected a finite decimal number"), std::string::npos) << message;
    }
  }
  for (const std::string text : {"45", "45.", ".5", "4.5e1", "-0", "1E1"})
    EXPECT_EQ(eval_refusal("model=lambert&law=h&theta_j=" + text).first, 0) << text;
  EXPECT_EQ(eval_refusal("model=lambert&law=h&theta_j=1&tol=0x1p-20").first, 400);
  const std::vector<std::pair<std::string, std::string>> cases{
      {"model=lambert&law=g&theta_i=10&theta_j=10&phi=1e308",
       "phi=1e+308 is out of range; allowed: [-360, 360] degrees"},
      {"model=lambert&law=g&theta_i=10&theta_j=10&phi=-361", "phi=-361 is out of range"},
      {"model=1.7e308*lambert %2B 1.7e308*lambert&law=h&theta_j=1", "sum to more than the largest number"},
  };
  expect_eval_refusals(cases);
}

TEST(ServeRequest, MixturesOfMoreLobesThanTheLimitAre413) {
  std::string spec = "lambert";
  for (int k = 1; k < 17; ++k) spec += "%2Bhvd-fit:r1=1e-6,n1=1e6";
  const auto [status, message] = eval_refusal("model=" + spec + "&law=h&theta_j=1");
  EXPECT_EQ(status, 413);
  EXPECT_NE(message.find("is a mixture of 17 lobes; this service computes at most 16"), std::string::npos) << message;
  EXPECT_EQ(table_refusal("model=" + spec + "&law=h").first, 413);
  Limits wider;
  wider.max_lobes = 17;
  EXPECT_NO_THROW(parse_eval(parse_query("model=" + spec + "&law=h&theta_j=1"), wider));
}

TEST(ServeRequest, TableUsesTheCacheKeysOfBake) {
  const TableQuery q = parse_table(parse_query("model=minnaert:xi=1&law=g&res=8x6x4&encoding=half&format=ktx2"),
                                   Limits{}, TableEndpoint::table);
  EXPECT_EQ(std::get<tables::BakeOptions>(q.options).resolution, (std::vector<int>{8, 6, 4}));
  EXPECT_EQ(tables::common(q.options).encoding, tables::Encoding::half);
  EXPECT_EQ(q.format, TableFormat::ktx2);
  // res or tol asks for that table, as bake model --res/--tol does: no search to an error target,
  // even where the defaults are one
  const TableQuery tol_only = parse_table(parse_query("model=minnaert:xi=1&law=h&tol=1e-6"), Limits{},
                                          TableEndpoint::table, scene::TableOptions::scene_defaults());
  ASSERT_TRUE(std::holds_alternative<tables::BakeOptions>(tol_only.options));
  EXPECT_EQ(std::get<tables::BakeOptions>(tol_only.options).resolution, scene::TableOptions{}.resolution_h);
  const tables::TableKey key = tables::table_key(*q.model, q.law, q.options);
  EXPECT_EQ(q.key, tables::key_text(key));
  EXPECT_EQ(q.file_name, tables::cache_file_name(key));
  EXPECT_EQ(q.file_name.find('/'), std::string::npos);
  // unset parameters: the scene defaults, so the service and `bake scene` share entries
  const TableQuery d = parse_table(parse_query("model=minnaert:xi=1&law=g"), Limits{}, TableEndpoint::table);
  EXPECT_EQ(std::get<tables::BakeOptions>(d.options).resolution, scene::TableOptions{}.resolution_g);
  EXPECT_EQ(std::get<tables::BakeOptions>(d.options).tolerance, scene::TableOptions{}.tolerance);
  // the service's defaults (serve/service.h): a query without res or tol is baked to the scene's target
  const TableQuery s = parse_table(parse_query("model=minnaert:xi=1&law=g"), Limits{}, TableEndpoint::table,
                                   scene::TableOptions::scene_defaults());
  const auto* scene_target = std::get_if<tables::TargetBake>(&s.options);
  ASSERT_NE(scene_target, nullptr);
  EXPECT_EQ(scene_target->target.lookup_error, scene::kSceneTargetError);
  EXPECT_EQ(scene_target->target.max_fetches, scene::kSceneFetches);
  EXPECT_TRUE(scene_target->target.best_effort);
  // and, as max_error's target, within the service's own size cap
  Limits small;
  small.max_entries = 1000;
  const TableQuery capped = parse_table(parse_query("model=minnaert:xi=1&law=g"), small, TableEndpoint::table,
                                        scene::TableOptions::scene_defaults());
  EXPECT_EQ(std::get<tables::TargetBake>(capped.options).target.max_bytes, small.max_entries * sizeof(float));
  const TableQuery fixed = parse_table(parse_query("model=minnaert:xi=1&law=g&res=8x6x4"), Limits{},
                                       TableEndpoint::table, scene::TableOptions::scene_defaults());
  EXPECT_TRUE(std::holds_alternative<tables::BakeOptions>(fixed.options));
}

// max_error asks for an error target, nothing else: no grid field is carried along to be
// silently replaced, and the target is capped at the service's own table size.
TEST(ServeRequest, MaxErrorIsAnErrorTarget) {
  Limits limits;
  const TableQuery q = parse_table(parse_query("model=minnaert:xi=1&law=g&max_error=1e-3&fetches=1&encoding=half"),
                                   limits, TableEndpoint::table);
  const auto* bake = std::get_if<tables::TargetBake>(&q.options);
  ASSERT_NE(bake, nullptr);
  EXPECT_EQ(bake->target.lookup_error, 1e-3);
  EXPECT_EQ(bake->target.max_bytes, limits.max_entries * sizeof(float));
  EXPECT_EQ(bake->target.max_fetches, 1);
  EXPECT_FALSE(bake->target.best_effort);
  EXPECT_EQ(bake->encoding, tables::Encoding::half);
  EXPECT_EQ(bake->max_evaluations, limits.max_evaluations);
  EXPECT_NE(q.key.find("max_error=0.001"), std::string::npos) << q.key;
  // max_error alone: strict, and searching every scheme as a scene's --max-error does, even where
  // the defaults are the scene's best-effort one-fetch target
  const TableQuery strict = parse_table(parse_query("model=minnaert:xi=1&law=g&max_error=1e-3"), limits,
                                        TableEndpoint::table, scene::TableOptions::scene_defaults());
  const auto* strict_bake = std::get_if<tables::TargetBake>(&strict.options);
  ASSERT_NE(strict_bake, nullptr);
  EXPECT_EQ(strict_bake->target.max_fetches, scene::kSceneSearchFetches);
  EXPECT_FALSE(strict_bake->target.best_effort);
}

TEST(ServeRequest, TableRefusals) {
  const std::vector<std::tuple<std::string, int, std::string>> cases{
      {"model=../../etc/passwd&law=h", 400, "unknown model '../../etc/passwd'"},
      {"model=lambert&law=f", 400, "has no table; allowed: g, h, a"},
      {"model=lambert&law=h&res=0", 400, "res='0' is not a resolution"},
      {"model=lambert&law=h&res=../x", 400, "res='../x' is not a resolution"},
      {"model=lambert&law=g&res=99999999999", 400, "is not a resolution"},
      {"model=lambert&law=g&res=100", 413, "res=100x100x100 is 1000000 entries; this service bakes at most 262144"},
      {"model=lambert&law=h&encoding=double", 400, "unknown encoding 'double'; allowed: half, float"},
      {"model=lambert&law=h&format=png", 400, "unknown format 'png'; allowed: exr, ktx2, json"},
      {"model=ward-aniso&law=h", 400, "anisotropic"},
      {"model=tabulated:file=x.tab&law=h", 400, "names a data file"},
  };
  for (const auto& [query, status, fragment] : cases) {
    const auto [got, message] = table_refusal(query);
    EXPECT_EQ(got, status) << query;
    EXPECT_NE(message.find(fragment), std::string::npos) << query << " -> " << message;
  }
  // max_error: as bake --max-error, named as the query names it
  for (const auto& [query, fragment] :
       {std::pair{"model=lambert&law=h&max_error=-1", "max_error=-1 is not allowed; expected a positive number"},
        std::pair{"model=lambert&law=h&max_error=1e-3&res=9", "give res or max_error, not both"},
        std::pair{"model=lambert&law=h&max_error=1e-3&tol=1e-6", "give tol or max_error, not both"},
        std::pair{"model=lambert&law=h&res=9&fetches=1", "fetches needs max_error"}}) {
    const auto [got, message] = table_refusal(query);
    EXPECT_EQ(got, 400) << query;
    EXPECT_NE(message.find(fragment), std::string::npos) << query << " -> " << message;
  }
  const auto [status, message] =
      refusal([] { parse_table(parse_query("model=lambert&law=h&format=exr"), Limits{}, TableEndpoint::glsl); });
  EXPECT_EQ(status, 400) << "/api/glsl has no format";
  EXPECT_NE(message.find("unknown parameter 'format' for /api/glsl"), std::string::npos) << message;
}

// serve/request_head.h: what the connection loop decides before httplib sees a head.
TEST(ServeHead, CompleteHeadsLoseRangeAndKeepTheRest) {
  const std::string head =
      "GET /api/table?x=1 HTTP/1.1\r\nHost: 127.0.0.1\r\nRange: bytes=0-9\r\n"
      "If-Range: \"e\"\r\nContent-Length: 0\r\nIf-None-Match: *\r\n\r\n";
  const HeadScan scan = scan_head("\r\n" + head + "GET /next", 32768);
  ASSERT_EQ(scan.verdict, HeadScan::Verdict::complete) << scan.message;
  EXPECT_EQ(scan.consumed, 2 + head.size()) << "a leading empty line is skipped; the next request stays";
  EXPECT_EQ(scan.head,
            "GET /api/table?x=1 HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 0\r\nIf-None-Match: *\r\n\r\n");
  EXPECT_EQ(scan.request_line, "GET /api/table?x=1 HTTP/1.1");
  EXPECT_EQ(scan_head("GET / HTTP/1.1\r\nrange:  bytes=1-\r\n\r\n", 32768).head, "GET / HTTP/1.1\r\n\r\n");
}

TEST(ServeHead, IncompleteRefusedAndBodies) {
  EXPECT_EQ(scan_head("GET / HTTP/1.1\r\nHost: a\r\n", 32768).verdict, HeadScan::Verdict::incomplete);
  EXPECT_EQ(scan_head("GET / HTTP/1.1\r\nHost: a\r", 32768).verdict, HeadScan::Verdict::incomplete);
  EXPECT_EQ(scan_head("", 32768).verdict, HeadScan::Verdict::incomplete);
  const std::vector<std::pair<std::string, int>> refused{
      {"GET / HTTP/1.1\r\nContent-Length: 5\r\n\r\nhello", 413},
      {"GET / HTTP/1.1\r\ncontent-length:7\r\n\r\n", 413},
      {"GET / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n", 413},
      {"GET / HTTP/1.1\nHost: a\n\n", 400},
      {"GET / HTTP/1.1\r\nHost: a\nX: b\r\n\r\n", 400},
      {"GET / HTTP/1.1\r\nHost: a\rX: b\r\n\r\n", 400},
      {"GET / HTTP/1.1\r\nX: a\r\n b\r\n\r\n", 400},
      {"GET / HTTP/1.1\r\nContent-Length : 5\r\n\r\n", 400},
      {"GET / HTTP/1.1\r\nno colon\r\n\r\n", 400},
      {std::string("GET / HTTP/1.1\r\nX: a\0b\r\n\r\n", 26), 400},
      {"GET / HTTP/1.1\r\nX: " + std::string(100, 'a'), 431},
  };
  for (const auto& [text, status] : refused) {
    const HeadScan scan = scan_head(text, 64);
    EXPECT_EQ(scan.verdict, HeadScan::Verdict::refused) << text;
    EXPECT_EQ(scan.status, status) << text << " -> " << scan.message;
    EXPECT_EQ(scan.message.find('\n'), std::string::npos);
  }
  EXPECT_EQ(scan_head("GET / HTTP/1.1\r\nContent-Length: 00\r\n\r\n", 64).verdict, HeadScan::Verdict::complete);
}

TEST(ServeHost, LocalNamesAndTheAllowedOnes) {
  const std::vector<std::string> allowed{"localhost", "127.0.0.1", "::1", "viewer.test"};
  for (const char* host : {"localhost", "LOCALHOST:8080", "127.0.0.1:1", "[::1]:8080", "[::1]", "viewer.test:80"})
    EXPECT_TRUE(host_allowed(host, allowed)) << host;
  for (const char* host : {"", "evil.example", "evil.example:8080", "localhost.evil.example", "127.0.0.1.nip.io", "::1",
                           "[::1", "localhost:80:80"})
    EXPECT_FALSE(host_allowed(host, allowed)) << host;
  EXPECT_TRUE(host_allowed("anything:1", {"*"}));
}

TEST(ServeEtag, StrongContentTagsAndIfNoneMatch) {
  const std::string tag = strong_etag("bytes");
  EXPECT_EQ(tag, strong_etag("bytes"));
  EXPECT_NE(tag, strong_etag("bytez"));
  EXPECT_EQ(tag.front(), '"');
  EXPECT_EQ(tag.rfind("\"fnv1a64:", 0), 0u);
  EXPECT_TRUE(if_none_match(tag, tag));
  EXPECT_TRUE(if_none_match("\"other\", W/" + tag, tag));
  EXPECT_TRUE(if_none_match(" * ", tag));
  EXPECT_FALSE(if_none_match("\"other\"", tag));
  EXPECT_FALSE(if_none_match("", tag));
}

/// `threads` threads submit at once (released together by a latch); returns the tickets' results
/// as the number of fake bakes that ran and how many submissions were refused.
struct Burst {
  int bakes = 0, refused = 0, joined = 0;
};
Burst burst(Bakery& bakery, int threads, bool same_key) {
  std::atomic<int> bakes{0}, refused{0}, joined{0};
  std::latch start(threads);
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      start.arrive_and_wait();
      try {
        const Bakery::Ticket ticket = bakery.submit(same_key ? "key" : "key" + std::to_string(t), [&](const auto&) {
          ++bakes;
          std::this_thread::sleep_for(kFakeBake);
          return std::make_shared<const tables::CacheResult>();
        });
        joined += ticket.joined;
        bakery.wait(ticket, nullptr);
      } catch (const Busy&) { ++refused; }
    });
  for (std::thread& t : pool) t.join();
  return {bakes.load(), refused.load(), joined.load()};
}

TEST(ServeBakery, IdenticalConcurrentRequestsBakeOnce) {
  Bakery bakery(1, 0);  // no queue at all: only joining lets 16 requests through
  const Burst b = burst(bakery, 16, true);
  EXPECT_EQ(b.bakes, 1);
  EXPECT_EQ(b.joined, 15);
  EXPECT_EQ(b.refused, 0);
  EXPECT_EQ(bakery.stats().started, 1);
}

TEST(ServeBakery, ExcessWorkIsRefusedNotQueued) {
  Bakery bakery(2, 3);  // 2 running + 3 waiting: 5 of 12 distinct bakes are taken
  const Burst b = burst(bakery, 12, false);
  EXPECT_EQ(b.bakes, 5);
  EXPECT_EQ(b.refused, 7);
  EXPECT_EQ(bakery.stats().refused, 7);
}

TEST(ServeBakery, StopDiscardsQueuedBakesAndFinishesRunningOnes) {
  Bakery bakery(1, 2);
  std::atomic<int> finished{0};
  auto job = [&](const std::atomic<bool>&) {
    std::this_thread::sleep_for(kFakeBake);
    ++finished;
    return std::make_shared<const tables::CacheResult>();
  };
  const Bakery::Ticket running = bakery.submit("a", job);
  while (bakery.stats().running == 0) std::this_thread::yield();
  const Bakery::Ticket queued = bakery.submit("b", job);
  bakery.stop();
  EXPECT_NO_THROW(bakery.wait(running, nullptr));
  EXPECT_THROW(bakery.wait(queued, nullptr), Busy);
  EXPECT_EQ(finished.load(), 1);
  EXPECT_THROW(bakery.submit("c", job), Busy);
}

/// A fake bake that runs until its flag is set (or `limit` passes), as tables::bake does.
Bakery::Job until_cancelled(std::atomic<int>& cancelled, std::chrono::milliseconds limit = std::chrono::seconds(20)) {
  return [&cancelled, limit](const std::atomic<bool>& stop) -> Bakery::Result {
    const auto end = std::chrono::steady_clock::now() + limit;
    while (!stop && std::chrono::steady_clock::now() < end) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    if (!stop) return std::make_shared<const tables::CacheResult>();
    ++cancelled;
    throw Cancelled("cancelled");
  };
}

TEST(ServeBakery, ABakeNobodyWaitsForIsCancelled) {
  Bakery bakery(1, 1);
  std::atomic<int> cancelled{0};
  Cancellation first, second;
  const Bakery::Ticket a = bakery.submit("slow", until_cancelled(cancelled));
  const Bakery::Ticket b = bakery.submit("slow", until_cancelled(cancelled));  // joins
  EXPECT_TRUE(b.joined);
  std::thread waiter_b([&] { EXPECT_THROW(bakery.wait(b, &second), Cancelled); });
  first.cancel(StopReason::client_gone);
  try {
    bakery.wait(a, &first);
    ADD_FAILURE() << "a cancelled request waited on";
  } catch (const Cancelled& e) {
    EXPECT_NE(std::string(e.what()).find("client closed the connection"), std::string::npos) << e.what();
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(cancelled.load(), 0) << "cancelled while a waiter remained";
  second.cancel(StopReason::deadline);  // the last waiter leaves: the bake stops
  waiter_b.join();
  for (int k = 0; k < 500 && bakery.stats().running > 0; ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(cancelled.load(), 1);
  EXPECT_EQ(bakery.stats().cancelled, 1);
  EXPECT_EQ(bakery.stats().running, 0);

  // Queued, then left by its only waiter: dropped before it starts.
  const Bakery::Ticket running = bakery.submit("running", until_cancelled(cancelled));
  while (bakery.stats().running == 0) std::this_thread::yield();
  const Bakery::Ticket queued = bakery.submit("queued", until_cancelled(cancelled));
  Cancellation gone;
  gone.cancel(StopReason::client_gone);
  EXPECT_THROW(bakery.wait(queued, &gone), Cancelled);
  EXPECT_EQ(bakery.stats().queued, 0);
  EXPECT_EQ(bakery.stats().discarded, 1);
  bakery.cancel_running();  // shutdown: the running one stops
  try {
    bakery.wait(running, nullptr);
    ADD_FAILURE() << "cancel_running did not stop the bake";
  } catch (const Cancelled& e) {
    EXPECT_NE(std::string(e.what()).find("shutting down"), std::string::npos) << e.what();
  }
}

TEST(ServeBakery, ABakeOverItsBudgetIsCancelled) {
  constexpr double kBudget = 0.2;  // seconds
  Bakery bakery(1, 0, kBudget);
  std::atomic<int> cancelled{0};
  const Bakery::Ticket t = bakery.submit("slow", until_cancelled(cancelled));
  try {
    bakery.wait(t, nullptr);
    ADD_FAILURE() << "a bake over its budget ran on";
  } catch (const Cancelled& e) {
    EXPECT_NE(std::string(e.what()).find("s per request"), std::string::npos) << e.what();
  }
  EXPECT_EQ(cancelled.load(), 1);
}

class ServeService : public ::testing::Test {
 protected:
  static std::string cache() {
    const std::string dir = testing_support::temp_dir() + "/serve-cache";
    std::filesystem::create_directories(dir);
    return dir;
  }
  Service service{[] {
    ServiceOptions o;
    o.cache_dir = cache();
    return o;
  }()};
  Reply get(const std::string& path, const std::string& query, const std::string& if_none_match = "") {
    return service.handle(path, query, if_none_match);
  }
  std::string header(const Reply& r, const std::string& name) {
    for (const auto& [key, value] : r.headers)
      if (key == name) return value;
    return "";
  }
};

TEST_F(ServeService, TableIsBakedOnceThenServedWithItsEtag) {
  const std::string query = "model=minnaert:xi=1&law=h&res=9&tol=1e-6";
  const Reply first = get("/api/table", query);
  ASSERT_EQ(first.status, 200) << first.body;
  EXPECT_EQ(first.content_type, "image/x-exr");
  EXPECT_EQ(header(first, "ETag"), strong_etag(first.body));
  EXPECT_NE(header(first, "Cache-Control").find("immutable"), std::string::npos);
  const Reply again = get("/api/table", query);
  EXPECT_EQ(header(again, "X-Ganzfeld-Table"), "reused");
  EXPECT_EQ(again.body, first.body);
  const Reply not_modified = get("/api/table", query, header(first, "ETag"));
  EXPECT_EQ(not_modified.status, 304);
  EXPECT_TRUE(not_modified.body.empty());
  EXPECT_EQ(get("/api/table", query, "\"fnv1a64:0000000000000000\"").status, 200);
  // one file in the cache, under the cache's own name
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(cache())) files += entry.path().extension() == ".exr";
  EXPECT_EQ(files, 1u);
  const auto health = nlohmann::json::parse(get("/healthz", "").body);
  EXPECT_EQ(health["tables_baked"], 1);
}

TEST_F(ServeService, ErrorsAreOneLineJson) {
  for (const auto& [path, query, status] :
       std::vector<std::tuple<std::string, std::string, int>>{{"/api/eval", "model=lambert&law=q", 400},
                                                              {"/api/table", "model=lambert&law=g&res=1000", 413},
                                                              {"/etc/passwd", "", 404},
                                                              {"/api/models", "x=1", 400},
                                                              {"/api/eval", "model=%", 400}}) {
    const Reply r = get(path, query);
    EXPECT_EQ(r.status, status) << path << "?" << query;
    const auto doc = nlohmann::json::parse(r.body);
    ASSERT_TRUE(doc.contains("error")) << r.body;
    EXPECT_EQ(doc["error"].get<std::string>().find('\n'), std::string::npos);
  }
}

// The viewer parses no spec itself: /api/spec answers with the parser's form (the parameters as
// given, a choice by name) and the model's canonical spec, the cache's key.
TEST_F(ServeService, SpecIsParsedByTheOneParser) {
  const Reply r = get("/api/spec", "model=ggx:g2=separable,roughness=0.5");
  ASSERT_EQ(r.status, 200) << r.body;
  const auto doc = nlohmann::json::parse(r.body);
  EXPECT_EQ(doc["canonical"], "ggx:alpha=0.25,f0=1,g2=separable");
  ASSERT_EQ(doc["terms"].size(), 1u);
  EXPECT_EQ(doc["terms"][0]["model"], "ggx");
  EXPECT_EQ(doc["terms"][0]["weight"], 1.0);
  EXPECT_EQ(doc["terms"][0]["parameters"], (nlohmann::json{{"roughness", 0.5}, {"g2", "separable"}}));
  const auto mixture = nlohmann::json::parse(get("/api/spec", "model=1*lambert %2B 3*specular").body);
  EXPECT_EQ(mixture["canonical"], "0.25*lambert + 0.75*specular:alpha=8");
  ASSERT_EQ(mixture["terms"].size(), 2u);
  EXPECT_EQ(mixture["terms"][1]["weight"], 0.75);
  EXPECT_TRUE(mixture["terms"][1]["parameters"].empty());
  for (const auto& [query, fragment] : std::vector<std::pair<std::string, std::string>>{
           {"model=specular:alpha=0", "alpha=0 is out of range"},
           {"model=merl:file=/etc/passwd", "names a data file"},
           {"", "missing parameter 'model'"},
           {"model=lambert&law=h", "unknown parameter 'law' for /api/spec; allowed: model"}}) {
    const Reply bad = get("/api/spec", query);
    EXPECT_EQ(bad.status, 400) << query;
    EXPECT_NE(nlohmann::json::parse(bad.body)["error"].get<std::string>().find(fragment), std::string::npos)
        << bad.body;
  }
}

TEST_F(ServeService, EvalAnswersAsTheCommandLine) {
  const Reply r = get("/api/eval", "model=lambert&law=h&theta_j=30");
  ASSERT_EQ(r.status, 200) << r.body;
  const auto doc = nlohmann::json::parse(r.body);
  EXPECT_NEAR(doc["value"].get<double>(), 1.0, 1e-9);  // K&P: h = 1 for a white Lambert surface
  EXPECT_EQ(doc["law"], "h");
  EXPECT_TRUE(doc["converged"].get<bool>());
}

// 16 hvd-fit lobes at a tolerance no budget meets: minutes of work unless stopped.
const std::string kExpensiveEval = [] {
  std::string spec = "hvd-fit:r1=1e-6,n1=1e6";
  for (int k = 1; k < 16; ++k) spec += "%2Bhvd-fit:r1=1e-6,n1=1e6";
  return "model=" + spec + "&law=g&theta_i=30&theta_j=40&tol=1e-15";
}();

TEST_F(ServeService, AnEvalStopsWhenItsRequestIsCancelled) {
  Cancellation cancel;
  std::thread later([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    cancel.cancel(StopReason::deadline);
  });
  const Reply r = service.handle("/api/eval", kExpensiveEval, "", &cancel);
  later.join();
  EXPECT_EQ(r.status, 503) << r.body;
  EXPECT_NE(nlohmann::json::parse(r.body)["error"].get<std::string>().find("s per request"), std::string::npos)
      << r.body;
  EXPECT_EQ(header(r, "Retry-After"), "") << "retrying the same request cannot help";
  Cancellation shutdown;
  shutdown.cancel(StopReason::shutdown);
  const Reply s = service.handle("/api/eval", kExpensiveEval, "", &shutdown);
  EXPECT_EQ(s.status, 503);
  EXPECT_NE(header(s, "Retry-After"), "");
  EXPECT_EQ(nlohmann::json::parse(get("/healthz", "").body)["requests_computing"], 0);
}

TEST(ServeServiceLimits, ComputingSlotsAreBounded) {
  ServiceOptions o;
  o.cache_dir = testing_support::temp_dir();
  o.max_computing = 1;
  Service service(o);
  Cancellation cancel;
  std::thread busy([&] { EXPECT_EQ(service.handle("/api/eval", kExpensiveEval, "", &cancel).status, 503); });
  while (nlohmann::json::parse(service.handle("/healthz", "", "").body)["requests_computing"] == 0)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const Reply refused = service.handle("/api/eval", "model=lambert&law=h&theta_j=10", "");
  EXPECT_EQ(refused.status, 503);
  EXPECT_NE(refused.body.find("computing slots are taken"), std::string::npos) << refused.body;
  EXPECT_EQ(service.handle("/api/models", "", "").status, 200) << "a cheap request needs no slot";
  cancel.cancel(StopReason::client_gone);
  busy.join();
  EXPECT_EQ(service.handle("/api/eval", "model=lambert&law=h&theta_j=10", "").status, 200);
}

TEST_F(ServeService, IfNoneMatchStarAnswers304WithoutBaking) {
  const std::string query = "model=minnaert:xi=2&law=h&res=9&tol=1e-6";
  const Reply r = get("/api/table", query, "*");
  EXPECT_EQ(r.status, 304);
  EXPECT_TRUE(r.body.empty());
  EXPECT_EQ(header(r, "ETag"), "");
  EXPECT_EQ(nlohmann::json::parse(get("/healthz", "").body)["tables_baked"], 0);
  EXPECT_EQ(get("/api/table", query, " * ").status, 304);
  EXPECT_EQ(get("/api/table", query, "\"fnv1a64:0000000000000000\"").status, 200);  // a tag needs the body
}

TEST(ServeServiceLimits, CacheFailuresAre500WithoutTheCachePath) {
  const std::string dir = testing_support::temp_dir() + "/cache-with-a-directory";
  std::filesystem::create_directories(dir);
  ServiceOptions o;
  o.cache_dir = dir;
  std::vector<std::string> logged;
  o.log = [&](const std::string& line) { logged.push_back(line); };
  Service service(o);
  const std::string query = "model=minnaert:xi=3&law=h&res=9&tol=1e-6";
  const TableQuery q = parse_table(parse_query(query), Limits{}, TableEndpoint::table);
  std::filesystem::create_directories(dir + "/" + q.file_name + "/inside");
  const Reply r = service.handle("/api/table", query, "");
  EXPECT_EQ(r.status, 500) << r.body;
  EXPECT_NE(r.body.find(q.file_name), std::string::npos) << r.body;
  EXPECT_EQ(r.body.find(dir), std::string::npos) << r.body;
  EXPECT_EQ(r.body.find(std::filesystem::absolute(dir).string()), std::string::npos) << r.body;
  EXPECT_EQ(r.body.find("/tmp"), std::string::npos) << r.body;
  ASSERT_FALSE(logged.empty());
  EXPECT_NE(logged.back().find(dir), std::string::npos) << "the operator's log names the path: " << logged.back();
}

TEST(ServeServiceLimits, DrainingRefusesBakesAndSaysSo) {
  ServiceOptions o;
  o.cache_dir = testing_support::temp_dir();
  Service service(o);
  service.drain();
  const Reply health = service.handle("/healthz", "", "");
  EXPECT_EQ(health.status, 503);
  EXPECT_EQ(nlohmann::json::parse(health.body)["status"], "draining");
  const Reply bake = service.handle("/api/table", "model=minnaert:xi=4&law=h&res=9", "");
  EXPECT_EQ(bake.status, 503);
  EXPECT_NE(bake.body.find("shutting down"), std::string::npos) << bake.body;
  EXPECT_EQ(service.handle("/api/models", "", "").status, 200);
}

TEST(ServeServiceLimits, StaleTemporaryFilesAreRemovedAtStart) {
  namespace fs = std::filesystem;
  const std::string dir = testing_support::temp_dir() + "/stale";
  fs::create_directories(dir);
  const fs::path stale = fs::path(dir) / ".specular_alpha=8.g.0123456789abcdef.exr.tmp-999999-0";
  const fs::path fresh = fs::path(dir) / ".specular_alpha=8.g.0123456789abcdef.exr.tmp-999999-1";
  const fs::path table = fs::path(dir) / "specular_alpha=8.g.0123456789abcdef.exr";
  for (const fs::path& p : {stale, fresh, table}) std::ofstream(p) << "x";
  fs::last_write_time(stale, fs::file_time_type::clock::now() - std::chrono::hours(2));
  fs::last_write_time(table, fs::file_time_type::clock::now() - std::chrono::hours(2));
  ServiceOptions o;
  o.cache_dir = dir;
  o.max_request_seconds = 60.0;
  std::string logged;
  o.log = [&](const std::string& line) { logged += line; };
  const Service service(o);
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(fresh)) << "younger than a bake's budget: maybe a writer at work";
  EXPECT_TRUE(fs::exists(table));
  EXPECT_NE(logged.find("removed 1 temporary file"), std::string::npos) << logged;
}

}  // namespace
}  // namespace ganzfeld::serve
