#include "reports/fit_report_text.h"

#include "reports/report_text.h"

namespace thermocomp {

using report_text::Code;
using report_text::Fixed;
using report_text::Join;
using report_text::P;
using report_text::Text;
using report_text::Um;

std::string FitReportMarkdown(const FitReport& r, const PlantTime& time) {
  std::string md = "# Model " + Text(r.machine) + " axis " + Text(r.axis) + " v" +
                   (r.version ? std::to_string(*r.version) : std::string("?")) + "\n\n";
  md += "**" + Text(r.status) + "**: " + Text(r.reason) + ". Created " + time.Format(r.created_ms) +
        " (" + Text(r.trigger) + "). Declared inputs: " + Join(r.declared_inputs) +
        "; kept: " + Join(r.model.inputs) + ". " + std::to_string(r.fit.n) + " probe points of " +
        std::to_string(r.training_runs) + " training runs.\n\n";
  md +=
      "## Coefficients (µm per unit of each term)\n\n| term | estimate | std. error | t | p | VIF "
      "|\n|---|---|---|---|---|---|\n";
  for (const TermStats& t : r.fit.terms) {
    md += "| " + Code(t.name) + " | " + Fixed(t.estimate * 1000.0, "%.4g") + " | " +
          Fixed(t.std_error * 1000.0, "%.3g") + " | " + Fixed(t.t, "%.3g") + " | " + P(t.p) +
          " | " + Fixed(t.vif, "%.3g") + " |\n";
  }
  md += "\nR² " + Fixed(r.fit.r2, "%.4f") + ", adjusted " + Fixed(r.fit.adj_r2, "%.4f") +
        "; residual sigma " + Um(r.fit.sigma) + " µm; F " + Fixed(r.fit.f, "%.4g") + " (p " +
        P(r.fit.f_p) + "); Durbin-Watson " + Fixed(r.fit.durbin_watson, "%.3f") + ".\n\n";
  md += "## Errors (µm)\n\n| | RMSE | R² | points |\n|---|---|---|---|\n";
  md += "| training | " + Um(r.fit.rmse) + " | " + Fixed(r.fit.r2, "%.4f") + " | " +
        std::to_string(r.fit.n) + " |\n";
  md += "| leave-one-run-out cross-validation | " + Um(r.cross_validation.rmse_mm) + " | " +
        Fixed(r.cross_validation.r2, "%.4f") + " | " + std::to_string(r.cross_validation.n) +
        " folds |\n";
  md += "| held-out runs (" + Join(r.validation_runs) + ") | " + Um(r.validation.rmse_mm) + " | " +
        Fixed(r.validation.r2, "%.4f") + " | " + std::to_string(r.validation.n) + " |\n\n";
  if (r.compared_with) {
    md += "Against version " + std::to_string(r.compared_with->version) +
          ", active then, on the same held-out points: " + Um(r.compared_with->active_rmse_mm) +
          " µm, this version " + Um(r.compared_with->candidate_rmse_mm) + " µm.\n\n";
  }
  md += "## Acceptance\n\n" +
        (r.accepted ? std::string("Passed.") : "Failed: " + Join(r.acceptance_reasons) + ".") +
        "\n\n## Removed\n\n";
  md += std::to_string(r.removed_outliers) + " outlier(s) in " + std::to_string(r.outlier_steps) +
        " step(s); " + std::to_string(r.skipped_gross_errors) + " gross error(s) and " +
        std::to_string(r.skipped_no_datum) + " point(s) without a datum skipped.";
  if (r.skipped_unserved > 0) {
    md += " " + std::to_string(r.skipped_unserved) +
          " point(s) probed with compensation active skipped: no served offset within a day to "
          "recover their raw drift.";
  }
  md += "\n\n";
  if (!r.removed_terms.empty()) {
    md += "| term | reason | p | VIF |\n|---|---|---|---|\n";
    for (const RemovedTerm& t : r.removed_terms) {
      md += "| " + Code(t.name) + " | " + Text(t.reason) + " | " + P(t.p) + " | " +
            Fixed(t.vif, "%.3g") + " |\n";
    }
    md += "\n";
  }
  if (!r.residuals.largest.empty()) {
    md +=
        "## Largest standardized residuals\n\n| run | point | time | value |\n|---|---|---|---|\n";
    for (const NamedResidual& n : r.residuals.largest) {
      md += "| " + Text(n.run) + " | " + std::to_string(n.k) + " | " + time.Format(n.ts_ms) +
            " | " + Fixed(n.value, "%.2f") + " |\n";
    }
  }
  return md;
}

}  // namespace thermocomp
