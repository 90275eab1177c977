// The service without HTTP (serve/): request validation and its one-line errors, the query
// decoder, ETags, single-flight bakes on a bounded queue, and whole requests through
// Service::handle against a temporary cache. tests/serve_test.sh runs the real server.
#include <atomic>
#include <chrono>
#include <filesystem>
#include <latch>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "serve/bakery.h"
#include "serve/etag.h"
#include "serve/request.h"
#include "serve/service.h"
#include "tests/temp_dir.h"

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
  } catch (const RequestError& e) {
    return {e.status(), e.what()};
  }
  return {0, ""};
}

std::pair<int, std::string> eval_refusal(const std::string& query) {
  return refusal([&] { parse_eval(parse_query(query), Limits{}); });
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
  const EvalQuery q = parse_eval(parse_query("model=specular:alpha=8&law=g&theta_i=120&theta_j=30&phi=180&tol=1e-8"), Limits{});
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
  for (const auto& [query, fragment] : cases) {
    const auto [status, message] = eval_refusal(query);
    EXPECT_EQ(status, 400) << query;
    EXPECT_NE(message.find(fragment), std::string::npos) << query << " -> " << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << "one line: " << message;
  }
}

TEST(ServeRequest, TableUsesTheCacheKeysOfBake) {
  const TableQuery q = parse_table(parse_query("model=minnaert:xi=1&law=g&res=8x6x4&encoding=half&format=ktx2"), Limits{},
                                   TableEndpoint::table);
  EXPECT_EQ(std::get<tables::BakeOptions>(q.options).resolution, (std::vector<int>{8, 6, 4}));
  EXPECT_EQ(tables::common(q.options).encoding, tables::Encoding::half);
  EXPECT_EQ(q.format, TableFormat::ktx2);
  const tables::TableKey key = tables::table_key(*q.model, q.law, q.options);
  EXPECT_EQ(q.key, tables::key_text(key));
  EXPECT_EQ(q.file_name, tables::cache_file_name(key));
  EXPECT_EQ(q.file_name.find('/'), std::string::npos);
  // unset parameters: the scene defaults, so the service and `bake --scene` share entries
  const TableQuery d = parse_table(parse_query("model=minnaert:xi=1&law=g"), Limits{}, TableEndpoint::table);
  EXPECT_EQ(std::get<tables::BakeOptions>(d.options).resolution, scene::TableOptions{}.resolution_g);
  EXPECT_EQ(std::get<tables::BakeOptions>(d.options).tolerance, scene::TableOptions{}.tolerance);
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
  EXPECT_EQ(bake->encoding, tables::Encoding::half);
  EXPECT_EQ(bake->max_evaluations, limits.max_evaluations);
  EXPECT_NE(q.key.find("max_error=0.001"), std::string::npos) << q.key;
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
  const auto [status, message] = refusal([] { parse_table(parse_query("model=lambert&law=h&format=exr"), Limits{}, TableEndpoint::glsl); });
  EXPECT_EQ(status, 400) << "/api/glsl has no format";
  EXPECT_NE(message.find("unknown parameter 'format' for /api/glsl"), std::string::npos) << message;
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
        const Bakery::Ticket ticket = bakery.submit(same_key ? "key" : "key" + std::to_string(t), [&] {
          ++bakes;
          std::this_thread::sleep_for(kFakeBake);
          return std::make_shared<const tables::CacheResult>();
        });
        joined += ticket.joined;
        ticket.result.get();
      } catch (const Busy&) {
        ++refused;
      }
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
  auto job = [&] {
    std::this_thread::sleep_for(kFakeBake);
    ++finished;
    return std::make_shared<const tables::CacheResult>();
  };
  const Bakery::Ticket running = bakery.submit("a", job);
  while (bakery.stats().running == 0) std::this_thread::yield();
  const Bakery::Ticket queued = bakery.submit("b", job);
  bakery.stop();
  EXPECT_NO_THROW(running.result.get());
  EXPECT_THROW(queued.result.get(), Busy);
  EXPECT_EQ(finished.load(), 1);
  EXPECT_THROW(bakery.submit("c", job), Busy);
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
  for (const auto& [path, query, status] : std::vector<std::tuple<std::string, std::string, int>>{
           {"/api/eval", "model=lambert&law=q", 400},
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
    EXPECT_NE(nlohmann::json::parse(bad.body)["error"].get<std::string>().find(fragment), std::string::npos) << bad.body;
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

}  // namespace
}  // namespace ganzfeld::serve
