#include "hw/netlist_tables.h"

namespace gpusim {

nlohmann::ordered_json to_json(const NetlistTables& t) {
  using json = nlohmann::ordered_json;
  const auto unit = [](int u) { return u < 0 ? json(nullptr) : json(u); };
  json stages = json::array();
  for (size_t i = 0; i < t.stages.size(); ++i) {
    const NetlistTables::Stage& s = t.stages[i];
    json inputs = json::array(), outputs = json::array();
    for (int f : s.inputs) inputs.push_back(t.fifos[f].name);
    for (int f : s.outputs) outputs.push_back(t.fifos[f].name);
    stages.push_back({{"index", i},
                      {"name", s.name},
                      {"kind", s.kind},
                      {"unit", unit(s.unit)},
                      {"inputs", inputs},
                      {"outputs", outputs},
                      {"item", s.item},
                      {"drops", json(s.drops)},
                      {"fragments", s.fragments.empty() ? json(nullptr) : json(s.fragments)}});
  }
  json fifos = json::array();
  for (size_t i = 0; i < t.fifos.size(); ++i) {
    const NetlistTables::Fifo& f = t.fifos[i];
    fifos.push_back({{"index", i},
                     {"name", f.name},
                     {"kind", f.kind},
                     {"depth", f.depth},
                     {"writer", f.writer < 0 ? json("host") : json(t.stages[f.writer].name)},
                     {"reader", f.reader < 0 ? json(nullptr) : json(t.stages[f.reader].name)},
                     {"unit", unit(f.unit)}});
  }
  const auto stage = [&](int s) { return s < 0 ? json(nullptr) : json(t.stages[s].name); };
  json clients = json::array();
  for (size_t i = 0; i < t.memory_clients.size(); ++i) {
    const NetlistTables::MemoryClient& c = t.memory_clients[i];
    clients.push_back({{"index", i}, {"name", c.name}, {"stage", stage(c.stage)}});
  }
  json links = json::array();
  for (size_t i = 0; i < t.links.size(); ++i) {
    const NetlistTables::Link& l = t.links[i];
    links.push_back({{"index", i},
                     {"name", l.name},
                     {"kind", l.kind},
                     {"writer", stage(l.writer)},
                     {"reader", stage(l.reader)},
                     {"unit", unit(l.unit)}});
  }
  return {{"stages", stages}, {"fifos", fifos}, {"memory_clients", clients}, {"links", links}};
}

}  // namespace gpusim
