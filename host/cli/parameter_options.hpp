#pragma once
// Command-line options for a stage's build parameters (io/parameters.hpp): --NAME for each, from the
// stage's own list, so `splatcl splats`, `splatcl csm build` and `splatcl batch` cannot drift apart.
// Values are collected as (option, value) pairs and applied by the command after parsing: an Error
// thrown from inside CLI11's parser would not reach the one-line error report.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "io/parameters.hpp"

namespace splatcl::cli {

using GivenParameters = std::vector<std::pair<std::string, nlohmann::json>>;  // ("--k", "12"), ("--clip", true)

// `defaults` (a stage's to_json of its default parameters) gives the "(default ...)" of each help line.
inline void add_parameter_options(CLI::App& app, const std::vector<ParameterInfo>& parameters, const nlohmann::json& defaults,
                                  const std::shared_ptr<GivenParameters>& given) {
  for (const ParameterInfo& p : parameters) {
    const std::string option = option_name(p.key);
    std::string help = p.help;
    // Flags default to off, and an empty text (no texture) is no default worth showing.
    if (const auto d = defaults.find(p.key); !p.flag && d != defaults.end() && !(d->is_string() && d->get<std::string>().empty()))
      help += " (default " + (d->is_string() ? d->get<std::string>() : d->is_number_float() ? fmt::format("{:g}", d->get<double>()) : d->dump()) + ")";
    if (p.flag)
      app.add_flag_callback(option, [given, option] { given->emplace_back(option, true); }, help);
    else
      app.add_option_function<std::string>(option, [given, option](const std::string& value) { given->emplace_back(option, value); }, help)
          ->type_name(p.path ? "FILE" : "VALUE");
  }
}

}  // namespace splatcl::cli
