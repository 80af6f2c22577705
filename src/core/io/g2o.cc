#include "rrr/io/g2o.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <charconv>
#include <fstream>
#include <initializer_list>
#include <optional>
#include <set>

#include "rrr/io/input_error.h"
#include "rrr/io/text_fields.h"

namespace rrr {
namespace {

enum class Dimension { kUnknown, k2D, k3D };

struct PendingVertex {
  int line;
  std::vector<double> values;
};

struct PendingEdge {
  int line;
  PoseId from, to;
  std::vector<double> values;
};

// Writes each of `values` after a space, in the shortest form that reads
// back as the same double.
void WriteNumbers(std::initializer_list<double> values, std::ostream& out) {
  char text[32];
  for (const double v : values) {
    out.put(' ');
    const std::to_chars_result end = std::to_chars(text, text + sizeof text, v);
    out.write(text, end.ptr - text);
  }
}

// Pose and information layouts of the two supported element types.
template <class Pose>
struct G2oTraits;

template <>
struct G2oTraits<Pose2> {
  static constexpr int kPoseFields = 3;
  static constexpr const char* kVertexTag = "VERTEX_SE2";
  static constexpr const char* kEdgeTag = "EDGE_SE2";
  static std::optional<Pose2> MakePose(const double* v, std::string*) {
    return Pose2(v[0], v[1], v[2]);
  }
  static void WritePose(const Pose2& p, std::ostream& out) {
    WriteNumbers({p.x(), p.y(), p.theta()}, out);
  }
};

template <>
struct G2oTraits<Pose3> {
  static constexpr int kPoseFields = 7;
  static constexpr const char* kVertexTag = "VERTEX_SE3:QUAT";
  static constexpr const char* kEdgeTag = "EDGE_SE3:QUAT";
  static std::optional<Pose3> MakePose(const double* v, std::string* problem) {
    // Normalized without overflow: components near 1e200 are a direction.
    const Eigen::Vector4d wxyz(v[6], v[3], v[4], v[5]);
    if (wxyz.stableNorm() < 1e-9) {
      *problem = "the quaternion has zero norm";
      return std::nullopt;
    }
    const Eigen::Vector4d unit = wxyz.stableNormalized();
    return Pose3(Eigen::Quaterniond(unit[0], unit[1], unit[2], unit[3]),
                 Eigen::Vector3d(v[0], v[1], v[2]));
  }
  static void WritePose(const Pose3& p, std::ostream& out) {
    const Eigen::Vector3d& t = p.translation();
    const Eigen::Quaterniond& q = p.quaternion();
    WriteNumbers({t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}, out);
  }
};

// Makes `information` positive definite (RepairedInformation) if it is not;
// returns its smallest eigenvalue as given when it was repaired. Throws
// InputError if no eigenvalue is positive, or, when `strict`, if any is not.
template <class Information>
std::optional<double> RepairInformation(Information* information,
                                        const PendingEdge& e,
                                        const std::string& source,
                                        bool strict) {
  const Eigen::LLT<Information> llt(*information);
  if (llt.info() == Eigen::Success) return std::nullopt;
  const auto problem = [&](const std::string& what) {
    return InputError(source, e.line,
                      "information matrix of edge " + std::to_string(e.from) +
                          " -> " + std::to_string(e.to) + " " + what);
  };
  if (strict) throw problem("is not positive definite");
  const Eigen::SelfAdjointEigenSolver<Information> eigen(*information);
  const auto& values = eigen.eigenvalues();  // ascending
  const double largest = values(values.size() - 1);
  if (!(largest > 0.0)) throw problem("has no positive eigenvalue");
  const double least = kLeastInformationRatio * largest;
  *information = eigen.eigenvectors() * values.cwiseMax(least).asDiagonal() *
                 eigen.eigenvectors().transpose();
  *information = 0.5 * (*information + information->transpose()).eval();
  return values(0);
}

template <class Pose>
PoseGraph<Pose> BuildGraph(const std::map<PoseId, PendingVertex>& vertices,
                           const std::vector<PendingEdge>& edges,
                           const std::vector<std::pair<int, PoseId>>& fixed,
                           const std::string& source, bool strict,
                           std::vector<SkippedCandidate>* skipped,
                           std::vector<RepairedInformation>* repaired) {
  using Traits = G2oTraits<Pose>;
  constexpr int kDof = Pose::kDof;
  PoseGraph<Pose> graph;
  std::string problem;
  // Pairs seen so far (ordered as given), with their values, and the lower
  // pose of each consecutive pair that has its odometry.
  std::map<std::pair<PoseId, PoseId>, std::vector<const PendingEdge*>> seen;
  std::set<PoseId> has_odometry;
  const auto skip = [&](const PendingEdge& e, CandidateDefect defect) {
    skipped->push_back({e.line, e.from, e.to, defect});
  };
  graph.Reserve(static_cast<int>(vertices.size()),
                static_cast<int>(edges.size()));
  for (const auto& [id, v] : vertices) {
    const std::optional<Pose> pose =
        Traits::MakePose(v.values.data(), &problem);
    if (!pose) throw InputError(source, v.line, problem);
    graph.AddPose(id, *pose);
  }
  for (const PendingEdge& e : edges) {
    typename PoseGraph<Pose>::Edge edge;
    edge.from = graph.IndexOf(e.from);
    edge.to = graph.IndexOf(e.to);
    if (e.from == e.to) {
      if (!strict) {
        skip(e, CandidateDefect::kSelfLoop);
        continue;
      }
      throw InputError(
          source, e.line,
          "edge connects vertex " + std::to_string(e.from) + " to itself");
    }
    if (edge.from < 0 || edge.to < 0) {
      if (!strict) {
        skip(e, CandidateDefect::kUnknownPose);
        continue;
      }
      throw InputError(source, e.line,
                       "edge refers to unknown vertex " +
                           std::to_string(edge.from < 0 ? e.from : e.to));
    }
    if (!strict) {
      auto& same_pair = seen[{e.from, e.to}];
      if (std::any_of(same_pair.begin(), same_pair.end(),
                      [&](const PendingEdge* other) {
                        return other->values == e.values;
                      })) {
        skip(e, CandidateDefect::kDuplicate);
        continue;
      }
      same_pair.push_back(&e);
      if (graph.IsOdometry(edge.from, edge.to) &&
          !has_odometry.insert(std::min(e.from, e.to)).second) {
        skip(e, CandidateDefect::kConsecutivePoses);
        continue;
      }
    }
    const std::optional<Pose> z = Traits::MakePose(e.values.data(), &problem);
    if (!z) throw InputError(source, e.line, problem);
    edge.measurement = *z;
    const double* upper = e.values.data() + Traits::kPoseFields;
    for (int r = 0, k = 0; r < kDof; ++r) {
      for (int c = r; c < kDof; ++c, ++k) {
        edge.information(r, c) = edge.information(c, r) = upper[k];
      }
    }
    const std::optional<double> smallest =
        RepairInformation(&edge.information, e, source, strict);
    if (smallest) repaired->push_back({e.line, e.from, e.to, *smallest});
    graph.AddEdge(edge);
  }
  for (const auto& [line, id] : fixed) {
    const int index = graph.IndexOf(id);
    if (index < 0) {
      throw InputError(source, line,
                       "FIX refers to unknown vertex " + std::to_string(id));
    }
    graph.Fix(index);
  }
  return graph;
}

}  // namespace

G2oFile ParseG2o(std::istream& in, const std::string& source, bool strict) {
  Dimension dim = Dimension::kUnknown;
  std::map<PoseId, PendingVertex> vertices;
  std::vector<PendingEdge> edges;
  std::vector<std::pair<int, PoseId>> fixed;
  std::map<std::string, int> skipped;

  const auto set_dimension = [&dim](Dimension d, const TextFields& f) {
    if (dim != Dimension::kUnknown && dim != d) {
      f.Fail("mixes 2D and 3D elements: " + std::string(f[0]) + " in a " +
             (dim == Dimension::k2D ? "2D" : "3D") + " file");
    }
    dim = d;
  };

  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    const TextFields f(text, source, line);
    if (f.IsComment()) continue;
    const std::string tag(f[0]);
    const bool is2d_vertex = tag == G2oTraits<Pose2>::kVertexTag;
    const bool is3d_vertex = tag == G2oTraits<Pose3>::kVertexTag;
    const bool is2d_edge = tag == G2oTraits<Pose2>::kEdgeTag;
    const bool is3d_edge = tag == G2oTraits<Pose3>::kEdgeTag;
    if (is2d_vertex || is3d_vertex) {
      set_dimension(is2d_vertex ? Dimension::k2D : Dimension::k3D, f);
      f.ExpectCount(2 + (is2d_vertex ? 3 : 7), tag);
      const PoseId id = f.Integer(1);
      if (vertices.count(id)) {
        f.Fail("vertex " + std::to_string(id) +
               " is defined twice (first on line " +
               std::to_string(vertices[id].line) + ")");
      }
      vertices[id] = PendingVertex{line, f.Numbers(2)};
    } else if (is2d_edge || is3d_edge) {
      set_dimension(is2d_edge ? Dimension::k2D : Dimension::k3D, f);
      f.ExpectCount(3 + (is2d_edge ? 3 + 6 : 7 + 21), tag);
      edges.push_back(
          PendingEdge{line, f.Integer(1), f.Integer(2), f.Numbers(3)});
    } else if (tag == "FIX") {
      if (f.size() < 2) f.Fail("FIX needs at least one vertex id");
      for (size_t k = 1; k < f.size(); ++k)
        fixed.emplace_back(line, f.Integer(k));
    } else {
      ++skipped[tag];
    }
  }
  if (in.bad()) throw InputError(source, 0, "read error");
  const bool poses_from_odometry = vertices.empty() && !edges.empty();
  if (vertices.empty()) {
    if (edges.empty()) throw InputError(source, 0, "no vertices and no edges");
    if (strict) throw InputError(source, 0, "no vertices");
    // Every id the edges name, at the identity until the chain places it.
    const std::vector<double> identity =
        dim == Dimension::k3D ? std::vector<double>{0, 0, 0, 0, 0, 0, 1}
                              : std::vector<double>{0, 0, 0};
    for (const PendingEdge& e : edges) {
      for (const PoseId id : {e.from, e.to}) {
        vertices.emplace(id, PendingVertex{e.line, identity});
      }
    }
  }

  G2oFile file;
  const auto build = [&](auto pose_tag) -> AnyPoseGraph {
    using Pose = decltype(pose_tag);
    PoseGraph<Pose> graph =
        BuildGraph<Pose>(vertices, edges, fixed, source, strict,
                         &file.skipped_candidates, &file.repaired_information);
    if (poses_from_odometry)
      graph.mutable_estimates() = graph.ComposeOdometry();
    return graph;
  };
  file.graph = dim == Dimension::k3D ? build(Pose3()) : build(Pose2());
  file.skipped_tags = std::move(skipped);
  file.poses_from_odometry = poses_from_odometry;
  return file;
}

G2oFile ReadG2o(const std::string& path, bool strict) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, "cannot open file");
  return ParseG2o(in, path, strict);
}

std::string DescribeSkipped(const std::map<std::string, int>& skipped_tags) {
  std::string out;
  for (const auto& [tag, count] : skipped_tags) {
    if (!out.empty()) out += ", ";
    out += tag + " x" + std::to_string(count);
  }
  return out;
}

template <class Pose>
void WriteG2o(const PoseGraph<Pose>& graph, const std::vector<Pose>& estimates,
              const std::vector<int>& loops, std::ostream& out) {
  using Traits = G2oTraits<Pose>;
  const auto& ids = graph.ids();
  for (int k = 0; k < graph.num_poses(); ++k) {
    out << Traits::kVertexTag << ' ' << ids[k];
    Traits::WritePose(estimates[k], out);
    out << '\n';
  }
  for (const int k : graph.fixed()) out << "FIX " << ids[k] << '\n';
  const auto write_edge = [&](const typename PoseGraph<Pose>::Edge& e) {
    out << Traits::kEdgeTag << ' ' << ids[e.from] << ' ' << ids[e.to];
    Traits::WritePose(e.measurement, out);
    for (int r = 0; r < Pose::kDof; ++r) {
      for (int c = r; c < Pose::kDof; ++c)
        WriteNumbers({e.information(r, c)}, out);
    }
    out << '\n';
  };
  for (const auto& e : graph.odometry()) write_edge(e);
  for (const int k : loops) write_edge(graph.loops().at(k));
}

template <class Pose>
void WriteG2oFile(const PoseGraph<Pose>& graph,
                  const std::vector<Pose>& estimates,
                  const std::vector<int>& loops, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw InputError(path, 0, "cannot open file for writing");
  WriteG2o(graph, estimates, loops, out);
  out.close();
  if (!out) throw InputError(path, 0, "write failed");
}

template void WriteG2o(const PoseGraph2&, const std::vector<Pose2>&,
                       const std::vector<int>&, std::ostream&);
template void WriteG2o(const PoseGraph3&, const std::vector<Pose3>&,
                       const std::vector<int>&, std::ostream&);
template void WriteG2oFile(const PoseGraph2&, const std::vector<Pose2>&,
                           const std::vector<int>&, const std::string&);
template void WriteG2oFile(const PoseGraph3&, const std::vector<Pose3>&,
                           const std::vector<int>&, const std::string&);

}  // namespace rrr
