// The module graph as documented against the one the build enforces: engine/CMakeLists.txt's
// d2vdb_add_module() calls (each module a static library linking its dependencies) are the truth;
// the table in engine/README.md ("Modules and their order") must list exactly those direct
// dependencies, and README.md's tree of engine/d2vdb/ exactly those modules.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace {

using Graph = std::map<std::string, std::set<std::string>>;

std::string readSourceFile(const std::string& relativePath) {
  std::ifstream file(std::string(D2VDB_SOURCE_DIR) + "/" + relativePath);
  EXPECT_TRUE(file) << "cannot read " << relativePath;
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

std::set<std::string> words(const std::string& text, const std::regex& pattern) {
  std::set<std::string> found;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), pattern);
       it != std::sregex_iterator(); ++it) {
    found.insert((*it)[1].str());
  }
  return found;
}

// Every d2vdb_add_module(NAME DEPENDS ...) call: NAME -> its d2vdb_* dependencies.
Graph graphFromCMake() {
  const std::string text = readSourceFile("engine/CMakeLists.txt");
  const std::regex call(R"(\nd2vdb_add_module\((\w+)([^)]*)\))");
  Graph graph;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), call); it != std::sregex_iterator();
       ++it) {
    graph[(*it)[1].str()] = words((*it)[2].str(), std::regex(R"(\bd2vdb_(\w+))"));
  }
  return graph;
}

// The rows "| `name` | `x`, `y` | ... |" of the engine/README.md table whose header row is
// `header` (the rows up to the first line that is not a table row).
std::string engineReadmeTable(const std::string& header) {
  const std::string text = readSourceFile("engine/README.md");
  const std::size_t start = text.find("\n" + header + "\n");
  EXPECT_NE(start, std::string::npos) << "engine/README.md has no table " << header;
  if (start == std::string::npos) return {};
  std::size_t end = start + 1;
  while (end < text.size() && text[end] == '|') {
    const std::size_t lineEnd = text.find('\n', end);
    end = lineEnd == std::string::npos ? text.size() : lineEnd + 1;
  }
  return text.substr(start, end - start);
}

// The rows "| `name` | `x`, `y` | ... |" of a table: name -> the words of its second cell.
Graph tableRows(const std::string& text) {
  const std::regex row(R"(\n\| `(\w+)` \| ([^|]*)\|)");
  Graph graph;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), row); it != std::sregex_iterator();
       ++it) {
    graph[(*it)[1].str()] = words((*it)[2].str(), std::regex("`([\\w.]+)`"));
  }
  return graph;
}

// engine/README.md's module table: module -> the modules it links.
Graph graphFromEngineReadme() {
  return tableRows(engineReadmeTable("| module | depends on | holds |"));
}

// The module folders drawn in README.md's tree of engine/d2vdb/ ("  name/  what it holds").
std::set<std::string> modulesFromReadme() {
  const std::string text = readSourceFile("README.md");
  const std::size_t start = text.find("\nengine/d2vdb/");
  EXPECT_NE(start, std::string::npos) << "README.md has no tree of engine/d2vdb/";
  const std::size_t end = text.find("\ntools/", start);
  return words(text.substr(start, end - start), std::regex(R"(\n  (\w+)/)"));
}

std::set<std::string> names(const Graph& graph) {
  std::set<std::string> keys;
  for (const auto& [name, dependencies] : graph) keys.insert(name);
  return keys;
}

TEST(ModuleGraph, EngineReadmeTableMatchesTheLinkGraph) {
  const Graph built = graphFromCMake();
  ASSERT_GE(built.size(), 10u) << "d2vdb_add_module() calls not found in engine/CMakeLists.txt";
  EXPECT_EQ(built.at("core"), std::set<std::string>{});
  EXPECT_EQ(graphFromEngineReadme(), built);
}

TEST(ModuleGraph, ReadmeTreeNamesEveryModule) {
  EXPECT_EQ(modulesFromReadme(), names(graphFromCMake()));
}

TEST(ModuleGraph, EntryHeadersExistInTheirModules) {
  // engine/README.md's "Where to start" table names, for every module, headers of that module.
  const Graph entries = tableRows(engineReadmeTable("| module | entry headers | one call does |"));
  EXPECT_EQ(names(entries), names(graphFromCMake()));
  for (const auto& [module, headers] : entries) {
    EXPECT_FALSE(headers.empty()) << module << " names no entry header";
    for (const std::string& header : headers) {
      const std::string path =
          std::string(D2VDB_SOURCE_DIR) + "/engine/d2vdb/" + module + "/" + header;
      EXPECT_TRUE(std::ifstream(path).good())
          << module << "'s entry header " << header << " is not " << path;
    }
  }
}

TEST(ModuleGraph, DependenciesPointOneWay) {
  // Every module's dependencies are modules, and no module depends on itself through others.
  const Graph graph = graphFromCMake();
  std::map<std::string, int> state;  // 1 = on the current path, 2 = done
  std::function<void(const std::string&)> visit = [&](const std::string& module) {
    state[module] = 1;
    for (const std::string& dependency : graph.at(module)) {
      ASSERT_TRUE(graph.count(dependency)) << module << " depends on unknown " << dependency;
      ASSERT_NE(state[dependency], 1) << "cycle through " << module << " -> " << dependency;
      if (state[dependency] == 0) visit(dependency);
    }
    state[module] = 2;
  };
  for (const auto& [module, dependencies] : graph) {
    if (state[module] == 0) visit(module);
  }
}

}  // namespace
