// `mutate --shard` and `mutate merge` (rayspace/mutate/mutate_shards.h): shards of a run merge into the
// run's own report, byte for byte; shards of different runs, a missing or a repeated shard are refused.
#include <doctest/doctest.h>

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayspace/mutate/mutate_shards.h"
#include "rayspace/error.h"
#include "rayspace/json_text.h"
#include "rayspace/shard.h"

namespace {

using nlohmann::json;
namespace shards = rayspace::app::mutate_shards;

json Mutant(std::size_t i, const char* status) {
  return {{"id", "trim.comp:" + std::to_string(40 + i) + ":3:relational:<"}, {"file", i % 3 ? "trim.comp" : "sort.comp"},
          {"passes", {"trim"}}, {"status", status}, {"index", i}};
}

// One run's report over `n` mutants and `v` variants on two sides, restricted to `shard`.
json Report(std::size_t n, std::size_t v, rayspace::Shard shard) {
  const char* statuses[] = {"killed", "survived", "killed", "equivalent", "stillborn"};
  std::vector<json> mutants, side;
  json variants = json::array();
  for (std::size_t i = 0; i < n; ++i)
    if (shard.Holds(i)) {
      mutants.push_back(Mutant(i, statuses[i % 5]));
      side.push_back(Mutant(i, statuses[(i + 1) % 5]));
    }
  for (std::size_t i = 0; i < v; ++i)
    if (shard.Holds(i)) variants.push_back({{"kernel", "trim.comp"}, {"recipe", "O"}, {"status", "equal"}, {"index", i}});
  json r = {{"seed", "1"}, {"backends", {"vulkan", "sim"}}, {"mutants_run", n}, {"variants_run", v}, {"configs", {{{"name", "crsh"}}}},
            {"mutants", mutants}, {"summary", shards::Summaries(mutants)}, {"variants", variants}, {"commit", "abc"}};
  r["on_sim"] = {{"configs", json::array()}, {"mutants_run", n}, {"mutants", side}, {"summary", shards::Summaries(side)},
                 {"differences", shards::Differences(mutants, side, "vulkan", "sim")}};
  if (shard.count > 1) r["shard"] = {{"index", shard.index}, {"count", shard.count}};
  return r;
}

}  // namespace

TEST_CASE("mutate shards: N shards of a run merge into the run's report, byte for byte, in any order") {
  const json whole = Report(11, 4, {0, 1});
  for (int n : {2, 3, 11, 12}) {
    std::vector<std::pair<std::string, json>> parts;
    for (int i = n - 1; i >= 0; --i) parts.emplace_back("shard" + std::to_string(i), Report(11, 4, {i, n}));
    CHECK(rayspace::JsonText(shards::Merge(parts)) == rayspace::JsonText(whole));
  }
}

TEST_CASE("mutate shards: a missing, repeated or foreign shard, or a report of no shard, is refused naming it") {
  const auto refused = [](std::vector<std::pair<std::string, json>> parts, const std::string& text) {
    try {
      shards::Merge(parts);
      FAIL("merged: " << text);
    } catch (const rayspace::InputError& e) {
      CHECK_MESSAGE(std::string(e.what()).find(text) != std::string::npos, e.what());
    }
  };
  refused({{"a.json", Report(5, 2, {0, 2})}}, "1 of the run's 2 shards");
  refused({{"a.json", Report(5, 2, {0, 2})}, {"b.json", Report(5, 2, {0, 2})}}, "b.json: shard 0/2 out of range or given twice");
  json other = Report(5, 2, {1, 2});
  other["seed"] = "2";
  refused({{"a.json", Report(5, 2, {0, 2})}, {"b.json", other}}, "b.json: not a shard of the same run as a.json");
  refused({{"a.json", Report(5, 2, {0, 1})}}, "a.json: not the report of a rayspace mutate --shard run");
  json lost = Report(5, 2, {1, 2});
  lost["mutants"].erase(0);
  refused({{"a.json", Report(5, 2, {0, 2})}, {"b.json", lost}}, "mutate merge: mutants 1 of 5 is in no shard's report");
  json twice = Report(5, 2, {1, 2});
  twice["mutants"].push_back(twice["mutants"][0]);
  refused({{"a.json", Report(5, 2, {0, 2})}, {"b.json", twice}}, "b.json: mutants with a missing, repeated or out-of-range index");
}

TEST_CASE("mutate shards: the report keeps no time and no scratch path") {
  json r = {{"seconds", 1.5}, {"configs", {{{"name", "crsh"}, {"seconds", 2.0}}}},
            {"reason", "/tmp/rayspace-mutate-x/mutants/0001/trim.comp:12: error; see /tmp/rayspace-mutate-x/log"}};
  shards::MakeDeterministic(r, "/tmp/rayspace-mutate-x");
  CHECK(rayspace::JsonText(r) ==
        rayspace::JsonText(json{{"configs", {{{"name", "crsh"}}}}, {"reason", "<work>/mutants/0001/trim.comp:12: error; see <work>/log"}}));
}
