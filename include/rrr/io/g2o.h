// Reading and writing pose graphs in the g2o text format.
#ifndef RRR_IO_G2O_H_
#define RRR_IO_G2O_H_

#include <iosfwd>
#include <map>
#include <string>
#include <variant>
#include <vector>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "rrr/graph/candidate_defect.h"
#include "rrr/graph/pose_graph.h"

namespace rrr {

using PoseGraph2 = PoseGraph<Pose2>;
using PoseGraph3 = PoseGraph<Pose3>;
using AnyPoseGraph = std::variant<PoseGraph2, PoseGraph3>;

// An edge that a place recogniser's output may hold but that is no usable
// loop candidate, and why.
struct SkippedCandidate {
  int line;
  PoseId from, to;
  // kConsecutivePoses: a further edge between consecutive poses (the first
  // is their odometry); kDuplicate: the same pair with the same measurement
  // and information as an earlier edge; kUnknownPose: a pose the file does
  // not have.
  CandidateDefect defect;
};

// An edge whose information matrix was not positive definite, replaced by
// the nearest positive definite matrix: the same eigenvectors, each
// eigenvalue raised to at least kLeastInformationRatio times the largest.
struct RepairedInformation {
  int line;
  PoseId from, to;
  double smallest_eigenvalue;  // as the file gave it
};
constexpr double kLeastInformationRatio = 1e-6;

// A parsed g2o file. Lines with tags other than VERTEX_SE2, EDGE_SE2,
// VERTEX_SE3:QUAT, EDGE_SE3:QUAT and FIX are skipped and counted by tag.
struct G2oFile {
  AnyPoseGraph graph;
  std::map<std::string, int> skipped_tags;
  // Degenerate candidates left out, in file order (empty when strict).
  std::vector<SkippedCandidate> skipped_candidates;
  // Information matrices repaired, in file order (empty when strict).
  std::vector<RepairedInformation> repaired_information;
  // The file had no vertices: its poses are the ids its edges name, placed
  // along its odometry chain from the identity.
  bool poses_from_odometry = false;
};

// Parses g2o text leniently, as real files come. Malformed input (missing
// or extra fields, a field that is not a finite number, a duplicate vertex,
// an information matrix without a positive eigenvalue, a zero quaternion, 2D
// and 3D elements in one file, a file without vertices or edges) throws
// InputError naming `source`, the line and the problem. What can be mended
// is mended and listed: degenerate candidates (SkippedCandidate) are left
// out, an information matrix that is not positive definite is repaired
// (RepairedInformation), and a file of edges only takes its poses from its
// odometry. With `strict`, each of these throws instead, except that
// duplicates and further edges between consecutive poses are kept (RRR
// judges duplicates, the solver uses every odometry edge).
G2oFile ParseG2o(std::istream& in, const std::string& source,
                 bool strict = false);
// Reads the file at `path`; throws InputError if it cannot be opened.
G2oFile ReadG2o(const std::string& path, bool strict = false);

// Human-readable summary of skipped tags ("VERTEX_XY x3, ..."), empty if none.
std::string DescribeSkipped(const std::map<std::string, int>& skipped_tags);

// Writes `graph` with `estimates` as vertex values, every odometry edge and
// the loops whose indices (into graph.loops()) are listed in `loops`, in the
// order given. Values are written with full double precision.
template <class Pose>
void WriteG2o(const PoseGraph<Pose>& graph, const std::vector<Pose>& estimates,
              const std::vector<int>& loops, std::ostream& out);
// Same, to a file; throws InputError if it cannot be written.
template <class Pose>
void WriteG2oFile(const PoseGraph<Pose>& graph,
                  const std::vector<Pose>& estimates,
                  const std::vector<int>& loops, const std::string& path);

// All loop indices 0..graph.loops().size()-1.
template <class Pose>
std::vector<int> AllLoops(const PoseGraph<Pose>& graph) {
  std::vector<int> all(graph.loops().size());
  for (size_t k = 0; k < all.size(); ++k) all[k] = static_cast<int>(k);
  return all;
}

}  // namespace rrr

#endif  // RRR_IO_G2O_H_
