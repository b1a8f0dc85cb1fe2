// SqliteSession: holds the Database's lock from construction to destruction
// (except while paused) and hands out the SQLite stores.
#pragma once

#include "storage/session.h"
#include "storage/sqlite/analysis_store.h"
#include "storage/sqlite/applied_store.h"
#include "storage/sqlite/aux_store.h"
#include "storage/sqlite/check_store.h"
#include "storage/sqlite/database.h"
#include "storage/sqlite/feed_model_store.h"
#include "storage/sqlite/log_store.h"
#include "storage/sqlite/machine_store.h"
#include "storage/sqlite/model_store.h"
#include "storage/sqlite/parts/part_model_store.h"
#include "storage/sqlite/parts/plate_store.h"
#include "storage/sqlite/parts/surface_store.h"
#include "storage/sqlite/parts/turning_store.h"
#include "storage/sqlite/probe_store.h"
#include "storage/sqlite/sample_store.h"

namespace thermocomp {

class SqliteSession final : public Session {
 public:
  explicit SqliteSession(Database& db);
  ~SqliteSession() override;
  SqliteSession(const SqliteSession&) = delete;
  SqliteSession& operator=(const SqliteSession&) = delete;

  MachineStore& machines() override { return machines_; }
  SampleStore& samples() override { return samples_; }
  ProbeStore& probes() override { return probes_; }
  ModelStore& models() override { return models_; }
  CheckStore& checks() override { return checks_; }
  AuxStore& aux() override { return aux_; }
  AnalysisStore& analyses() override { return analyses_; }
  LogStore& log() override { return log_; }
  FeedModelStore& feeds() override { return feeds_; }
  PlateStore& plates() override { return plates_; }
  TurningStore& turned_parts() override { return turned_parts_; }
  PartModelStore& part_models() override { return part_models_; }
  SurfaceStore& surfaces() override { return surfaces_; }
  AppliedStore& applied() override { return applied_; }

  Status Begin() override { return db_.Begin(); }
  Status Commit() override { return db_.Commit(); }
  void Rollback() override { db_.Rollback(); }
  void Pause() override;
  void Resume() override;

 private:
  Database& db_;
  bool held_ = false;
  SqliteMachineStore machines_;
  SqliteSampleStore samples_;
  SqliteProbeStore probes_;
  SqliteModelStore models_;
  SqliteCheckStore checks_;
  SqliteAuxStore aux_;
  SqliteAnalysisStore analyses_;
  SqliteLogStore log_;
  SqliteFeedModelStore feeds_;
  SqlitePlateStore plates_;
  SqliteTurningStore turned_parts_;
  SqlitePartModelStore part_models_;
  SqliteSurfaceStore surfaces_;
  SqliteAppliedStore applied_;
};

}  // namespace thermocomp
