#include "text/yaml_node_count.hpp"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/yaml.h>

#include <sstream>

namespace beamtrace::detail {
namespace {

/// Thrown by the handler to stop the parser once the count passes its limit.
struct Enough {};

class NodeCounter : public YAML::EventHandler {
  public:
    explicit NodeCounter(std::size_t stop_after) : stop_after_(stop_after) {}
    [[nodiscard]] std::size_t count() const { return count_; }

    void OnDocumentStart(const YAML::Mark&) override {}
    void OnDocumentEnd() override {}
    void OnNull(const YAML::Mark&, YAML::anchor_t) override { add(); }
    void OnAlias(const YAML::Mark&, YAML::anchor_t) override { add(); }
    void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  const std::string&) override {
        add();
    }
    void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                         YAML::EmitterStyle::value) override {
        add();
    }
    void OnSequenceEnd() override {}
    void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                    YAML::EmitterStyle::value) override {
        add();
    }
    void OnMapEnd() override {}

  private:
    void add() {
        if (++count_ > stop_after_) {
            throw Enough{};
        }
    }
    std::size_t stop_after_;
    std::size_t count_ = 0;
};

}  // namespace

std::size_t count_yaml_nodes(const std::string& text, std::size_t stop_after) {
    std::istringstream in(text);
    YAML::Parser parser(in);
    NodeCounter counter(stop_after);
    try {
        while (parser.HandleNextDocument(counter)) {
        }
    } catch (const Enough&) {
    }
    return counter.count();
}

}  // namespace beamtrace::detail
