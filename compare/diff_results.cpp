#include "compare/diff_results.h"

#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>

#include "compare/markup.h"

namespace nightcap {

namespace {

std::string number(double v) {
  std::ostringstream s;
  s << std::setprecision(6) << v;
  return s.str();
}

std::string measured(const OutputDiff& o) {
  const ResourceComparison& c = o.comparison;
  if (!c.comparable) return c.note;
  if (o.threshold) {
    if (!o.threshold->problem.empty()) return o.threshold->problem;
    return std::to_string(o.threshold->over) + " of " + std::to_string(o.threshold->counted) + " texels over, worst " +
           number(o.threshold->worst);
  }
  if (!o.contract.measure.empty()) return "worst " + number(o.contract.worst) + " " + o.contract.measure;
  return c.metric + " max abs " + number(c.max_abs);
}

// What differs of a frame's own inputs, and of the settings that likely made them differ.
std::string frame_inputs_message(const CaptureDiff& diff, const FrameDiff& frame) {
  std::string text = "the frame's own inputs differ: " + comma_separated(frame.inputs_differ);
  if (!diff.settings_differ.empty())
    text += "; the captures' settings differ: " + comma_separated(diff.settings_differ);
  if (!diff.scene_differ.empty()) text += "; the scenes' descriptions differ: " + comma_separated(diff.scene_differ);
  return text;
}

}  // namespace

std::vector<DiffCase> diff_cases(const CaptureDiff& diff) {
  using Outcome = DiffCase::Outcome;
  std::vector<DiffCase> cases;
  for (const FrameDiff& frame : diff.frames) {
    const std::string suite = "frame " + std::to_string(frame.index);
    if (!frame.inputs_differ.empty())
      cases.push_back({suite, "frame inputs", Outcome::failed, frame_inputs_message(diff, frame)});
    for (const PassDiff& p : frame.passes) {
      switch (p.status) {
        case PassStatus::skipped:
          cases.push_back({suite, p.name, Outcome::skipped, "skipped in both captures"});
          continue;
        case PassStatus::skipped_in_a:
        case PassStatus::skipped_in_b:
        case PassStatus::only_in_a:
        case PassStatus::only_in_b:
          cases.push_back({suite, p.name, Outcome::failed, status_name(p.status, diff.golden)});
          continue;
        default:
          break;
      }
      for (const OutputDiff& o : p.outputs) {
        DiffCase c{suite, p.name + "/" + o.resource, o.beyond || o.only_in_one ? Outcome::failed : Outcome::passed, ""};
        if (o.only_in_one)
          c.message = o.comparison.note;
        else if (o.comparison.identical)
          c.message = "identical; held to " + o.held_to;
        else
          c.message = "held to " + o.held_to + ": " + measured(o);
        if (p.isolation && !o.comparison.identical) c.message += "; " + isolation_summary(*p.isolation);
        cases.push_back(std::move(c));
      }
    }
  }
  for (const std::string& note : diff.notes) cases.push_back({"captures", note, Outcome::failed, note});
  return cases;
}

DiffTally tally(const std::vector<DiffCase>& cases) {
  DiffTally t;
  for (const DiffCase& c : cases) {
    t.passed += c.outcome == DiffCase::Outcome::passed;
    t.failed += c.outcome == DiffCase::Outcome::failed;
    t.skipped += c.outcome == DiffCase::Outcome::skipped;
  }
  return t;
}

void write_junit(const std::filesystem::path& file, const std::vector<DiffCase>& cases, double seconds) {
  std::map<std::string, std::vector<const DiffCase*>> suites;
  for (const DiffCase& c : cases) suites[c.suite].push_back(&c);
  const DiffTally all = tally(cases);
  std::ostringstream out;
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<testsuites name=\"nightcap diff\" tests=\"" << cases.size() << "\" failures=\"" << all.failed
      << "\" skipped=\"" << all.skipped << "\" time=\"" << number(seconds) << "\">\n";
  for (const auto& [suite, members] : suites) {
    uint64_t failures = 0, skipped = 0;
    for (const DiffCase* c : members) {
      failures += c->outcome == DiffCase::Outcome::failed;
      skipped += c->outcome == DiffCase::Outcome::skipped;
    }
    out << "  <testsuite name=\"" << escape_markup(suite) << "\" tests=\"" << members.size() << "\" failures=\""
        << failures << "\" skipped=\"" << skipped << "\">\n";
    for (const DiffCase* c : members) {
      out << "    <testcase classname=\"" << escape_markup(suite) << "\" name=\"" << escape_markup(c->name) << "\"";
      if (c->outcome == DiffCase::Outcome::passed) {
        out << ">\n      <system-out>" << escape_markup(c->message) << "</system-out>\n    </testcase>\n";
      } else {
        const char* element = c->outcome == DiffCase::Outcome::failed ? "failure" : "skipped";
        out << ">\n      <" << element << " message=\"" << escape_markup(c->message) << "\"/>\n    </testcase>\n";
      }
    }
    out << "  </testsuite>\n";
  }
  out << "</testsuites>\n";
  // Written beside the target and renamed, so a CI job never reads half a report.
  const std::filesystem::path partial = file.string() + ".partial";
  {
    std::ofstream stream(partial, std::ios::binary | std::ios::trunc);
    stream << out.str();
    stream.close();
    if (!stream) throw std::runtime_error(file.string() + ": cannot write");
  }
  std::error_code error;
  std::filesystem::rename(partial, file, error);
  if (error) {
    std::filesystem::remove(partial, error);
    throw std::runtime_error(file.string() + ": cannot write");
  }
}

}  // namespace nightcap
