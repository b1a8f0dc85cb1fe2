// SqlSession: holds the connection's lock from construction to destruction
// (except while paused) and hands out the shared SQL stores; the session of
// both backends.
#pragma once

#include "storage/session.h"
#include "storage/sql/analysis_store.h"
#include "storage/sql/applied_store.h"
#include "storage/sql/aux_store.h"
#include "storage/sql/check_store.h"
#include "storage/sql/connection.h"
#include "storage/sql/feed_model_store.h"
#include "storage/sql/log_store.h"
#include "storage/sql/machine_store.h"
#include "storage/sql/model_store.h"
#include "storage/sql/parts/part_model_store.h"
#include "storage/sql/parts/plate_store.h"
#include "storage/sql/parts/surface_store.h"
#include "storage/sql/parts/turning_store.h"
#include "storage/sql/probe_store.h"
#include "storage/sql/sample_store.h"

namespace thermocomp {

class SqlSession final : public Session {
 public:
  explicit SqlSession(SqlConnection& db);
  ~SqlSession() override;
  SqlSession(const SqlSession&) = delete;
  SqlSession& operator=(const SqlSession&) = delete;

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
  SqlConnection& db_;
  bool held_ = false;
  SqlMachineStore machines_;
  SqlSampleStore samples_;
  SqlProbeStore probes_;
  SqlModelStore models_;
  SqlCheckStore checks_;
  SqlAuxStore aux_;
  SqlAnalysisStore analyses_;
  SqlLogStore log_;
  SqlFeedModelStore feeds_;
  SqlPlateStore plates_;
  SqlTurningStore turned_parts_;
  SqlPartModelStore part_models_;
  SqlSurfaceStore surfaces_;
  SqlAppliedStore applied_;
};

}  // namespace thermocomp
