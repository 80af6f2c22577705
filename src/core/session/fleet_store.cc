#include "rrr/session/fleet_store.h"

#include <algorithm>
#include <map>
#include <utility>

#include "rrr/geometry/pose2.h"
#include "rrr/geometry/pose3.h"
#include "session_codec.h"
#include "session_tables.h"
#include "sqlite_db.h"

namespace rrr {
namespace {

// What a row of a fleet's inputs table is.
enum FleetInputKind : std::int64_t {
  kSessionStart = 0,      // a keyframe that started a session
  kNextKeyframe = 1,      // a keyframe of the robot's current session
  kCandidate = 2,         // by keyframe ids
  kCandidateByStamp = 3,  // by stamps (ns), in the columns of the ids
};

constexpr const char* kFleetSchema = R"sql(
CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE robots(robot INTEGER PRIMARY KEY, name TEXT NOT NULL UNIQUE);
CREATE TABLE inputs(
  seq INTEGER PRIMARY KEY,       -- arrival order
  kind INTEGER NOT NULL,  -- 0 session start, 1 keyframe, 2 candidate, 3 by stamp
  robot INTEGER NOT NULL,        -- keyframes; candidates: the from end's
  number INTEGER NOT NULL,       -- keyframe id, or candidate number (-1: waited)
  stamp_ns INTEGER,              -- keyframes
  odometry_pose BLOB,            -- keyframes: pose in the robot's odometry
  covariance BLOB,               -- keyframes: its 6 x 6 covariance (*)
  to_robot INTEGER,              -- candidates
  from_id INTEGER, to_id INTEGER,  -- candidates: keyframe ids (or stamps)
  measurement BLOB, information BLOB);  -- candidates (*)
-- (*) the upper triangle, row by row, if symmetric, else every entry.
)sql";

bool HasTable(SqliteDb* db, const std::string& name) {
  SqliteStatement query(
      db,
      "SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = ?");
  query.Bind(1, name);
  query.Step();
  return query.Int(0) == 1;
}

}  // namespace

bool IsFleetDatabase(SqliteDb* db) {
  if (!HasTable(db, "meta")) return false;
  SqliteStatement query(
      db, "SELECT count(*) FROM meta WHERE key = 'fleet_schema_version'");
  query.Step();
  return query.Int(0) == 1;
}

template <class Pose>
class FleetStore<Pose>::Impl {
 public:
  Impl(const std::string& path, const std::vector<std::string>& robots,
       const std::string& procedure)
      : db(path, true) {
    const int dimension = DimensionOf(static_cast<const Pose*>(nullptr));
    PrepareForRecording(
        &db, std::string(kFleetSchema) + kUpdatesSchema,
        {{"fleet_schema_version", std::to_string(kFleetSchemaVersion)},
         {"dimension", std::to_string(dimension)},
         {"procedure", procedure}});
    if (!IsFleetDatabase(&db)) {
      db.Fail(
          "it is not a fleet's session database (one robot's is resumed "
          "without robots)");
    }
    const std::string version = MetaValue(&db, "fleet_schema_version");
    if (version != std::to_string(kFleetSchemaVersion)) {
      db.Fail("fleet schema version " + version + ", but this rrr reads " +
              std::to_string(kFleetSchemaVersion));
    }
    for (const char* table : {"robots", "inputs", "updates", "decisions"}) {
      if (!HasTable(&db, table)) {
        db.Fail(std::string("it has no table ") + table);
      }
    }
    const std::string recorded = MetaValue(&db, "dimension");
    if (recorded != "2" && recorded != "3") {
      db.Fail("dimension " + recorded + " is neither 2 nor 3");
    }
    CheckRecordedAs(&db, "fleet", recorded == "2" ? 2 : 3, dimension,
                    procedure);
    // The recorded robots, and the new ones after them.
    SqliteStatement names(&db, "SELECT robot, name FROM robots ORDER BY robot");
    while (names.Step()) recorded_robots.push_back(names.Text(1));
    SqliteStatement add(&db, "INSERT INTO robots(robot, name) VALUES (?, ?)");
    for (const std::string& name : robots) {
      auto it = std::find(recorded_robots.begin(), recorded_robots.end(), name);
      if (it == recorded_robots.end()) {
        add.Bind(1, static_cast<std::int64_t>(recorded_robots.size()));
        add.Bind(2, name);
        add.Step();
        add.Reset();
        recorded_robots.push_back(name);
        it = recorded_robots.end() - 1;
      }
      stored_robot.push_back(it - recorded_robots.begin());
    }
    NextNumbers(&db, &next_seq, &next_update);
    insert_input = std::make_unique<SqliteStatement>(
        &db,
        "INSERT INTO inputs(seq, kind, robot, stamp_ns, odometry_pose, "
        "covariance, to_robot, from_id, to_id, measurement, information, "
        "number) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)");
    updates = std::make_unique<UpdateLog>(&db);
  }

  SqliteDb db;
  std::vector<std::string> recorded_robots;  // by stored index
  std::vector<std::int64_t> stored_robot;    // by the fleet's robot index
  std::unique_ptr<SqliteStatement> insert_input;
  std::unique_ptr<UpdateLog> updates;
  std::int64_t next_seq = 1, next_update = 1;
  // Rows recorded since the last commit.
  struct Pending {
    FleetInputKind kind;
    std::int64_t number = 0;
    std::int64_t robot = 0;
    KeyframeRecord<Pose> keyframe;
    std::int64_t to_robot = 0, from_id = 0, to_id = 0;
    std::vector<double> measurement, information;
  };
  std::vector<Pending> pending;
};

template <class Pose>
FleetStore<Pose>::FleetStore(const std::string& path,
                             const std::vector<std::string>& robots,
                             const std::string& procedure)
    : impl_(std::make_unique<Impl>(path, robots, procedure)) {}

template <class Pose>
FleetStore<Pose>::~FleetStore() = default;

template <class Pose>
const std::string& FleetStore<Pose>::path() const {
  return impl_->db.path();
}

template <class Pose>
int FleetStore<Pose>::num_uncommitted() const {
  return static_cast<int>(impl_->pending.size());
}

template <class Pose>
void FleetStore<Pose>::RecordKeyframe(
    int robot, const KeyframeRecord<Pose>& keyframe,
    const typename Fleet<Pose>::Taken& taken) {
  impl_->pending.push_back({taken.new_session ? kSessionStart : kNextKeyframe,
                            taken.id,
                            impl_->stored_robot.at(robot),
                            keyframe,
                            0,
                            0,
                            0,
                            {},
                            {}});
}

template <class Pose>
void FleetStore<Pose>::RecordCandidate(int number, int robot_a,
                                       std::int64_t id_a, int robot_b,
                                       std::int64_t id_b, const Pose& z,
                                       const Information& information) {
  impl_->pending.push_back({kCandidate, number, impl_->stored_robot.at(robot_a),
                            KeyframeRecord<Pose>{},
                            impl_->stored_robot.at(robot_b), id_a, id_b,
                            Encode(z), Encode(information)});
}

template <class Pose>
void FleetStore<Pose>::RecordCandidateByStamp(int number, int robot_a,
                                              std::int64_t stamp_a, int robot_b,
                                              std::int64_t stamp_b,
                                              const Pose& z,
                                              const Information& information) {
  impl_->pending.push_back(
      {kCandidateByStamp, number, impl_->stored_robot.at(robot_a),
       KeyframeRecord<Pose>{}, impl_->stored_robot.at(robot_b), stamp_a,
       stamp_b, Encode(z), Encode(information)});
}

template <class Pose>
void FleetStore<Pose>::CommitUpdate(
    bool finish, const std::vector<DecisionChange>& changes) {
  Impl& s = *impl_;
  std::int64_t seq = s.next_seq;
  s.db.Execute("BEGIN");
  try {
    SqliteStatement& insert = *s.insert_input;
    for (const typename Impl::Pending& row : s.pending) {
      for (int column = 1; column <= 11; ++column) insert.BindNull(column);
      insert.Bind(12, row.number);
      insert.Bind(1, seq++);
      insert.Bind(2, static_cast<std::int64_t>(row.kind));
      insert.Bind(3, row.robot);
      if (row.kind == kCandidate || row.kind == kCandidateByStamp) {
        insert.Bind(7, row.to_robot);
        insert.Bind(8, row.from_id);
        insert.Bind(9, row.to_id);
        insert.Bind(10, row.measurement);
        insert.Bind(11, row.information);
      } else {
        insert.Bind(4, row.keyframe.stamp_ns);
        insert.Bind(5, Encode(row.keyframe.odometry_pose));
        insert.Bind(6, Encode(row.keyframe.covariance));
      }
      insert.Step();
      insert.Reset();
    }
    s.updates->Append(s.next_update, seq - 1, finish, changes);
    s.db.Execute("COMMIT");
  } catch (...) {
    s.insert_input->Reset();
    s.updates->Reset();
    sqlite3_exec(s.db.handle(), "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
  s.next_seq = seq;
  ++s.next_update;
  s.pending.clear();
}

template <class Pose>
FleetResumeSummary FleetStore<Pose>::Resume(Fleet<Pose>* fleet) {
  Impl& s = *impl_;
  std::vector<int> robot_of_stored;
  for (const std::string& name : s.recorded_robots) {
    robot_of_stored.push_back(fleet->RobotIndex(name));
  }
  const auto robot = [&](std::int64_t stored, const std::string& at) {
    if (stored < 0 ||
        stored >= static_cast<std::int64_t>(robot_of_stored.size())) {
      s.db.Fail(at + "robot " + std::to_string(stored) + " is not recorded");
    }
    const int r = robot_of_stored[stored];
    if (r < 0) {
      s.db.Fail(at + "robot '" + s.recorded_robots[stored] +
                "' is recorded but not among the robots");
    }
    return r;
  };
  FleetResumeSummary summary;
  const std::vector<UpdateRow> updates = ReadUpdates(&s.db);
  size_t next = 0;
  // Each update replayed where it ran: the decisions depend only on the
  // inputs and their order.
  const auto run_updates_until = [&](std::int64_t seq) {
    for (; next < updates.size() && updates[next].last_seq <= seq; ++next) {
      if (updates[next].finish) {
        fleet->Finish();
      } else {
        fleet->Update();
      }
      ++summary.updates;
    }
  };
  run_updates_until(0);
  const size_t pose_size = EncodedSize(static_cast<const Pose*>(nullptr));
  SqliteStatement query(
      &s.db,
      "SELECT seq, kind, robot, stamp_ns, odometry_pose, covariance, "
      "to_robot, from_id, to_id, measurement, information, number FROM inputs "
      "ORDER BY seq");
  while (query.Step()) {
    const std::int64_t seq = query.Int(0);
    const std::string at = "input " + std::to_string(seq) + ": ";
    const auto fail = [&](const std::string& problem) {
      s.db.Fail(at + problem);
    };
    const std::int64_t kind = query.Int(1);
    const int from = robot(query.Int(2), at);
    try {
      if (kind == kCandidate || kind == kCandidateByStamp) {
        Pose z;
        Information information;
        DecodeMeasurement(s.db, query, 9, 10, at, &z, &information);
        const int to = robot(query.Int(6), at);
        const int number =
            kind == kCandidate
                ? fleet->AddLoop(from, query.Int(7), to, query.Int(8), z,
                                 information)
                : fleet->AddLoopByStamp(from, query.Int(7), to, query.Int(8), z,
                                        information);
        if (number != query.Int(11)) {
          fail("the candidate recorded as number " +
               std::to_string(query.Int(11)) + " arrives as " +
               std::to_string(number));
        }
        ++summary.candidates;
      } else if (kind == kSessionStart || kind == kNextKeyframe) {
        KeyframeRecord<Pose> keyframe;
        keyframe.stamp_ns = query.Int(3);
        keyframe.odometry_pose =
            DecodePose(FiniteDoubles(s.db, query, 4, pose_size, "a pose", at),
                       static_cast<const Pose*>(nullptr), fail);
        keyframe.covariance =
            FiniteMatrix<6>(s.db, query, 5, "a covariance", at);
        const auto taken =
            fleet->AddKeyframe(from, keyframe, kind == kSessionStart);
        if (taken.id != query.Int(11)) {
          fail("the keyframe of robot '" + s.recorded_robots[query.Int(2)] +
               "' recorded as " + std::to_string(query.Int(11)) +
               " arrives as " + std::to_string(taken.id));
        }
        ++summary.keyframes;
        if (kind == kSessionStart) ++summary.sessions;
      } else {
        fail("unknown kind " + std::to_string(kind));
      }
    } catch (const std::logic_error& e) {  // the fleet refused it
      fail(e.what());
    }
    run_updates_until(seq);
  }
  run_updates_until(s.next_seq);
  const auto& verifier = fleet->verifier();
  for (const auto& [candidate, state] : ReadFinalStates(&s.db)) {
    if (candidate >= verifier.num_candidates() ||
        verifier.state(candidate) != state) {
      ++summary.differing_decisions;
    }
  }
  for (int r = 0; r < static_cast<int>(fleet->robots().size()); ++r) {
    if (!fleet->sessions(r).empty()) fleet->StartSession(r);
  }
  return summary;
}

bool IsFleetDatabase(const std::string& path) {
  if (!LooksLikeSessionDatabase(path)) return false;
  SqliteDb db(path, false);
  return IsFleetDatabase(&db);
}

template class FleetStore<Pose2>;
template class FleetStore<Pose3>;

}  // namespace rrr
