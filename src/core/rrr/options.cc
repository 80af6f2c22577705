#include "rrr/rrr/options.h"

#include <cstdio>
#include <functional>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

namespace rrr {

std::string RrrOptions::Validate() const {
  if (cluster_window < 1) {
    return "cluster_window must be at least 1, got " +
           std::to_string(cluster_window);
  }
  if (iterations < 1) {
    return "iterations must be at least 1, got " + std::to_string(iterations);
  }
  if (!(alpha > 0.0 && alpha < 1.0)) {
    return "alpha must be in (0, 1), got " + std::to_string(alpha);
  }
  if (threads < 1) {
    return "threads must be at least 1, got " + std::to_string(threads);
  }
  if (max_future_poses < 0) {
    return "max_future_poses must not be negative, got " +
           std::to_string(max_future_poses);
  }
  if (decision_delay < 0) {
    return "decision_delay must not be negative, got " +
           std::to_string(decision_delay);
  }
  if (max_waiting < 0) {
    return "max_waiting must not be negative, got " +
           std::to_string(max_waiting);
  }
  if (!(noise_scale >= 0.0)) {
    return "noise_scale must be positive, or 0 to estimate it, got " +
           std::to_string(noise_scale);
  }
  if (!(noise_margin > 0.0)) {
    return "noise_margin must be positive, got " + std::to_string(noise_margin);
  }
  if (map_radius < 1) {
    return "map_radius must be at least 1, got " + std::to_string(map_radius);
  }
  if (map_junctions < 1) {
    return "map_junctions must be at least 1, got " +
           std::to_string(map_junctions);
  }
  if (optimize_every < 1) {
    return "optimize_every must be at least 1, got " +
           std::to_string(optimize_every);
  }
  if (!(optimize_growth >= 0.0)) {
    return "optimize_growth must not be negative, got " +
           std::to_string(optimize_growth);
  }
  if (convergence.max_iterations < 1) {
    return "the iteration limit must be at least 1, got " +
           std::to_string(convergence.max_iterations);
  }
  return "";
}

const char* ToString(Procedure procedure) {
  return procedure == Procedure::kMap ? "map" : "published";
}

bool ParseProcedure(const std::string& name, Procedure* procedure) {
  if (name == "published") {
    *procedure = Procedure::kPublished;
  } else if (name == "map") {
    *procedure = Procedure::kMap;
  } else {
    return false;
  }
  return true;
}

namespace {

// Each option's name with a way to write it and to read it.
struct Field {
  const char* name;
  std::function<std::string(const RrrOptions&)> write;
  std::function<bool(const std::string&, RrrOptions*)> read;
};

std::string Exact(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.17g", v);
  return text;
}

template <class T>
bool ReadNumber(const std::string& text, T* value) {
  std::istringstream in(text);
  T v;
  if (!(in >> v) || !in.eof()) return false;
  *value = v;
  return true;
}

template <class T>
Field NumberField(const char* name, T RrrOptions::*member) {
  return {name,
          [member](const RrrOptions& o) {
            if constexpr (std::is_floating_point_v<T>) {
              return Exact(o.*member);
            } else {
              return std::to_string(o.*member);
            }
          },
          [member](const std::string& t, RrrOptions* o) {
            return ReadNumber(t, &(o->*member));
          }};
}

const std::vector<Field>& Fields() {
  static const std::vector<Field> fields = {
      {"procedure",
       [](const RrrOptions& o) { return std::string(ToString(o.procedure)); },
       [](const std::string& t, RrrOptions* o) {
         return ParseProcedure(t, &o->procedure);
       }},
      NumberField("cluster_window", &RrrOptions::cluster_window),
      NumberField("iterations", &RrrOptions::iterations),
      {"steps",
       [](const RrrOptions& o) {
         return std::string(o.steps == SolveSteps::kGaussNewton
                                ? "gauss_newton"
                                : "trust_region");
       },
       [](const std::string& t, RrrOptions* o) {
         if (t != "gauss_newton" && t != "trust_region") return false;
         o->steps = t == "gauss_newton" ? SolveSteps::kGaussNewton
                                        : SolveSteps::kTrustRegion;
         return true;
       }},
      NumberField("alpha", &RrrOptions::alpha),
      {"span_gate",
       [](const RrrOptions& o) { return std::string(o.span_gate ? "1" : "0"); },
       [](const std::string& t, RrrOptions* o) {
         if (t != "0" && t != "1") return false;
         o->span_gate = t == "1";
         return true;
       }},
      NumberField("threads", &RrrOptions::threads),
      NumberField("max_future_poses", &RrrOptions::max_future_poses),
      NumberField("max_waiting", &RrrOptions::max_waiting),
      NumberField("decision_delay", &RrrOptions::decision_delay),
      NumberField("noise_scale", &RrrOptions::noise_scale),
      NumberField("noise_margin", &RrrOptions::noise_margin),
      NumberField("map_radius", &RrrOptions::map_radius),
      NumberField("map_junctions", &RrrOptions::map_junctions),
      NumberField("optimize_every", &RrrOptions::optimize_every),
      NumberField("optimize_growth", &RrrOptions::optimize_growth),
      {"max_iterations",
       [](const RrrOptions& o) {
         return std::to_string(o.convergence.max_iterations);
       },
       [](const std::string& t, RrrOptions* o) {
         return ReadNumber(t, &o->convergence.max_iterations);
       }},
      {"relative_decrease",
       [](const RrrOptions& o) {
         return Exact(o.convergence.relative_decrease);
       },
       [](const std::string& t, RrrOptions* o) {
         return ReadNumber(t, &o->convergence.relative_decrease);
       }},
  };
  return fields;
}

}  // namespace

std::string OptionsText(const RrrOptions& options) {
  std::string text;
  for (const Field& f : Fields()) {
    if (!text.empty()) text += ' ';
    text += std::string(f.name) + "=" + f.write(options);
  }
  return text;
}

RrrOptions ParseOptionsText(const std::string& text) {
  RrrOptions options;
  std::istringstream in(text);
  std::string pair;
  while (in >> pair) {
    const size_t equals = pair.find('=');
    if (equals == std::string::npos) {
      throw std::invalid_argument("options: '" + pair + "' is not name=value");
    }
    const std::string name = pair.substr(0, equals);
    const std::string value = pair.substr(equals + 1);
    bool known = false;
    for (const Field& f : Fields()) {
      if (name != f.name) continue;
      known = true;
      if (!f.read(value, &options)) {
        throw std::invalid_argument("options: " + name + "=" + value +
                                    ": not a value of " + name);
      }
    }
    if (!known) throw std::invalid_argument("options: unknown option " + name);
  }
  return options;
}

}  // namespace rrr
