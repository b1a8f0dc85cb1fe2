#include "reports/parts/part_model_text.h"

#include "reports/report_text.h"

namespace thermocomp {
namespace {

using report_text::Code;
using report_text::Fixed;
using report_text::Join;
using report_text::Text;

std::string ScoreRow(const std::string& what, const PartHeldOutScore& s) {
  return "| " + what + " | " + Fixed(s.rmse, "%.2f") + " | " + Fixed(s.mae, "%.2f") + " | " +
         Fixed(s.r2, "%.2f") + " | " + Fixed(s.baseline_rmse, "%.2f") + " | " +
         (s.beats_baseline ? "yes" : "no") + " | " + std::to_string(s.refused) + " | " +
         Fixed(s.served_rmse, "%.2f") + " |\n";
}

}  // namespace

std::string PartFitReportMarkdown(const PartFitReport& r, const PlantTime& time) {
  std::string md = "# Part-error fit " + Text(r.machine) + " " + Code(r.target) + "\n\n";
  md += "**" + std::string(r.accepted ? "Accepted" : "Not accepted") + "**: " + Text(r.decision) +
        ". Served version for " + Code(r.target) + " after the fit: " +
        (r.active_version ? std::to_string(r.active_version) : std::string("none")) + ". Created " +
        time.Format(r.created_ms) + " by " + Text(r.actor) + ".\n\n";
  md += "## Records\n\n" + std::to_string(r.records) +
        " records: " + std::to_string(r.training_rows) + " for training, " +
        std::to_string(r.held_out.size()) + " held out at random (share " +
        Fixed(r.held_out_share, "%.2f") + ", seed " + std::to_string(r.seed) +
        "); the held-out records took no part in the ranking, the structure search or the "
        "training. Training mean " +
        Fixed(r.training_mean, "%.2f") + ".\n\n";
  md += "## Inputs by sensitivity\n\n";
  md += "Cross-validated (" + std::to_string(r.ranking.folds) + " folds of the training part, " +
        Text(r.ranking.structure) + "): RMSE with every input " +
        Fixed(r.ranking.cv_rmse_all, "%.2f") + ", predicting the mean " +
        Fixed(r.ranking.cv_rmse_mean, "%.2f") + ". An input is kept when the error without it is " +
        Fixed(r.ranking.threshold, "%.2f") + " times the error with all or more.\n\n";
  md += "| input | RMSE without | ratio | kept |\n|---|---|---|---|\n";
  for (const PartInputRank& i : r.ranking.inputs) {
    md += "| " + Code(i.name) + " | " + Fixed(i.cv_rmse_without, "%.2f") + " | " +
          Fixed(i.ratio, "%.3f") + " | " + (i.kept ? "yes" : "no") + " |\n";
  }
  md += "\nCandidates: " + Join(r.candidates) + ". Kept: " + Join(r.kept) + ".\n\n";
  md += "## Types on the held-out records\n\n";
  md +=
      "A record the guard refuses (an input outside the trained range) counts as the training "
      "mean; the last column is the RMSE over the records the model predicted.\n\n"
      "| model | RMSE | MAE | R² | mean's RMSE | beats the mean | refused | RMSE served |\n"
      "|---|---|---|---|---|---|---|---|\n";
  for (const PartTypeResult& t : r.types) {
    if (t.fitted) md += ScoreRow(Code(t.type) + " v" + std::to_string(t.version), t.held_out);
  }
  if (r.champion && r.champion->held_out) {
    md += ScoreRow(
        "active v" + std::to_string(r.champion->version) + " (" + Code(r.champion->type) + ")",
        *r.champion->held_out);
  }
  md += "\n";
  for (const PartTypeResult& t : r.types) {
    md += "- " + Code(t.type) + ": ";
    if (!t.fitted) {
      md += "not fitted: " + Text(t.error) + "\n";
      continue;
    }
    md += Text(t.status) + ", " + Text(t.reason) + ". Inputs " + Join(t.inputs) +
          "; training RMSE " + Fixed(t.training_rmse, "%.2f");
    if (!t.terms.empty()) md += "; terms " + Join(t.terms);
    if (t.hidden_units) {
      md += "; " + std::to_string(*t.hidden_units) + " hidden units, " +
            Fixed(t.effective_parameters.value_or(0), "%.1f") + " effective parameters";
    }
    md += ".\n";
  }
  if (r.champion && !r.champion->held_out) {
    md +=
        "- active v" + std::to_string(r.champion->version) + ": " + Text(r.champion->note) + ".\n";
  }
  return md;
}

}  // namespace thermocomp
