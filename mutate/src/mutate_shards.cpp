#include "rayspace/mutate/mutate_shards.h"

#include <algorithm>
#include <map>
#include <set>

#include "rayspace/error.h"

namespace rayspace::app::mutate_shards {
using nlohmann::json;

json Summaries(const std::vector<json>& mutants) {
  std::map<std::string, std::map<std::string, std::size_t>> per_file;
  std::map<std::string, std::vector<std::string>> passes_of;
  std::map<std::string, std::size_t> all;
  std::size_t unexplained = 0;
  for (const json& m : mutants) {
    const std::string file = m["file"], status = m["status"];
    ++per_file[file][status];
    ++all[status];
    passes_of[file] = m["passes"].get<std::vector<std::string>>();
    unexplained += status == "survived" && !m.contains("class");
  }
  const auto score = [](std::map<std::string, std::size_t>& c) {
    const std::size_t k = c["killed"], s = c["survived"];
    return k + s ? static_cast<double>(k) / (k + s) : 1.0;
  };
  json files = json::object();
  for (auto& [file, c] : per_file)
    files[file] = {{"passes", passes_of[file]}, {"killed", c["killed"]}, {"survived", c["survived"]}, {"equivalent", c["equivalent"]},
                   {"stillborn", c["stillborn"]}, {"invalid", c["invalid"]}, {"score", score(c)}};
  return {{"mutants", mutants.size()}, {"killed", all["killed"]}, {"survived", all["survived"]}, {"equivalent", all["equivalent"]},
          {"stillborn", all["stillborn"]}, {"invalid", all["invalid"]}, {"unexplained_survivors", unexplained}, {"score", score(all)},
          {"per_file", files}};
}

json Differences(const std::vector<json>& first, const std::vector<json>& second, const std::string& a, const std::string& b) {
  std::map<std::string, const json*> other;
  for (const json& m : second) other[m["id"].get<std::string>()] = &m;
  json out = json::array();
  for (const json& m : first) {
    const auto it = other.find(m["id"].get<std::string>());
    if (it == other.end() || m["status"] == (*it->second)["status"]) continue;
    const json& o = *it->second;
    json d = {{"id", m["id"]}, {"source", m.value("source", std::string())}, {a, m["status"]}, {b, o["status"]}};
    const json& killer = m["status"] == "killed" ? m : o;
    if (killer.contains("caught")) d["caught"] = killer["caught"];
    if (killer.contains("reason")) d["reason"] = killer["reason"];
    out.push_back(d);
  }
  return out;
}

void MakeDeterministic(json& report, const std::string& work) {
  if (report.is_object()) {
    report.erase("seconds");
    for (auto& [key, value] : report.items()) MakeDeterministic(value, work);
  } else if (report.is_array()) {
    for (json& v : report) MakeDeterministic(v, work);
  } else if (report.is_string() && !work.empty()) {
    std::string s = report.get<std::string>();
    for (std::size_t at = s.find(work); at != std::string::npos; at = s.find(work, at + 6)) s.replace(at, work.size(), "<work>");
    report = s;
  }
}

namespace {

// The members every shard of one run shares: all but the shard's own results.
json Shared(const json& report, const std::vector<std::string>& sides) {
  json s = report;
  for (const char* k : {"shard", "mutants", "summary", "variants"}) s.erase(k);
  for (std::size_t k = 1; k < sides.size(); ++k)
    if (s.contains("on_" + sides[k])) {
      json& side = s["on_" + sides[k]];
      for (const char* m : {"mutants", "summary", "differences"}) side.erase(m);
    }
  return s;
}

// The items of `key` in every shard, put back in their run's order by "index", which must run over
// 0 .. expected - 1 once each.
std::vector<json> Gather(const std::vector<std::pair<std::string, const json*>>& parts, std::size_t expected, const std::string& what) {
  std::vector<json> all(expected);
  std::vector<bool> seen(expected, false);
  for (const auto& [name, items] : parts) {
    if (!items->is_array()) ThrowInput("{}: '{}' is not a list", name, what);
    for (const json& item : *items) {
      const std::size_t i = item.is_object() && item.contains("index") && item["index"].is_number_unsigned() ? item["index"].get<std::size_t>()
                                                                                                               : expected;
      if (i >= expected || seen[i]) ThrowInput("{}: {} with a missing, repeated or out-of-range index", name, what);
      seen[i] = true;
      all[i] = item;
    }
  }
  for (std::size_t i = 0; i < expected; ++i)
    if (!seen[i]) ThrowInput("mutate merge: {} {} of {} is in no shard's report", what, i, expected);
  return all;
}

}  // namespace

json Merge(const std::vector<std::pair<std::string, json>>& shards) {
  if (shards.empty()) ThrowInput("mutate merge: no shard reports given");
  std::set<int> indexes;
  int count = 0;
  for (const auto& [name, r] : shards) {
    if (!r.is_object() || !r.contains("shard") || !r["shard"].is_object() || !r["shard"]["index"].is_number_integer() ||
        !r["shard"]["count"].is_number_integer() || !r.contains("backends") || !r["backends"].is_array() || r["backends"].empty())
      ThrowInput("{}: not the report of a rayspace mutate --shard run (no \"shard\" and \"backends\")", name);
    const int c = r["shard"]["count"].get<int>(), i = r["shard"]["index"].get<int>();
    if (count && c != count) ThrowInput("{}: shard of {} reports, the others of {}", name, c, count);
    count = c;
    if (i < 0 || i >= c || !indexes.insert(i).second) ThrowInput("{}: shard {}/{} out of range or given twice", name, i, c);
  }
  if (static_cast<int>(shards.size()) != count)
    ThrowInput("mutate merge: {} of the run's {} shards given; every shard exactly once", shards.size(), count);
  const std::vector<std::string> sides = shards.front().second["backends"].get<std::vector<std::string>>();
  const json shared = Shared(shards.front().second, sides);
  for (const auto& [name, r] : shards)
    if (Shared(r, sides) != shared) ThrowInput("{}: not a shard of the same run as {} (its options, baseline or version differ)", name,
                                               shards.front().first);
  json merged = shards.front().second;
  merged.erase("shard");
  const auto gather = [&](const std::string& side, const char* key, const std::string& count_key) {
    std::vector<std::pair<std::string, const json*>> parts;
    for (const auto& [name, r] : shards) parts.emplace_back(name, side.empty() ? &r[key] : &r["on_" + side][key]);
    const json& counts = side.empty() ? shared : shared["on_" + side];
    if (!counts.contains(count_key) || !counts[count_key].is_number_unsigned())
      ThrowInput("{}: no \"{}\"", shards.front().first, count_key);
    return Gather(parts, counts[count_key].get<std::size_t>(), key);
  };
  const std::vector<json> mutants = gather("", "mutants", "mutants_run");
  merged["mutants"] = mutants;
  merged["variants"] = gather("", "variants", "variants_run");
  merged["summary"] = Summaries(mutants);
  for (std::size_t k = 1; k < sides.size(); ++k) {
    const std::vector<json> side = gather(sides[k], "mutants", "mutants_run");
    json& on = merged["on_" + sides[k]];
    on["mutants"] = side;
    on["summary"] = Summaries(side);
    on["differences"] = Differences(mutants, side, sides[0], sides[k]);
  }
  return merged;
}

}  // namespace rayspace::app::mutate_shards
