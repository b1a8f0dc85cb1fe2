# Independent reference for the model tests: R's lm(), car::vif() and the
# selection procedure of docs/model.md section 4, on the measured study data.
# Regenerate with:  Rscript tests/reference/fms_reference.R shared/data/fms_datum_drift.csv > tests/reference/fms_reference.txt
# (Debian packages r-base-core, r-cran-car, r-cran-lmtest). The C++ tests read the .txt only.
args <- commandArgs(trailingOnly = TRUE)
d <- read.csv(if (length(args) > 0) args[1] else "../shared/data/fms_datum_drift.csv")
sensors <- c("dT_co", "dT_cl", "dT_x1", "dT_x2", "dT_env", "dT_y1", "dT_y2", "dT_z")

out <- function(key, value) cat(sprintf("%s %.17g\n", key, value))

fit_terms <- function(data, terms, response) {
  rhs <- if (length(terms) == 0) "1" else paste(terms, collapse = " + ")
  lm(as.formula(paste(response, "~", rhs)), data = data)
}

dump_fit <- function(prefix, f, terms) {
  s <- summary(f)
  cf <- coef(s)
  out(paste0(prefix, ".n"), nrow(model.frame(f)))
  out(paste0(prefix, ".r2"), s$r.squared)
  out(paste0(prefix, ".adj_r2"), s$adj.r.squared)
  if (length(terms) > 0) {
    out(paste0(prefix, ".f"), s$fstatistic[1])
    out(paste0(prefix, ".f_p"), pf(s$fstatistic[1], s$fstatistic[2], s$fstatistic[3], lower.tail = FALSE))
  }
  e <- residuals(f)
  out(paste0(prefix, ".rmse"), sqrt(sum(e^2) / length(e)))
  out(paste0(prefix, ".sigma"), s$sigma)
  out(paste0(prefix, ".dw"), sum(diff(e)^2) / sum(e^2))
  v <- if (length(terms) > 1) car::vif(f) else setNames(rep(1, length(terms)), terms)
  for (i in seq_len(nrow(cf))) {
    name <- if (i == 1) "intercept" else rownames(cf)[i]
    out(paste0(prefix, ".", name, ".estimate"), cf[i, 1])
    out(paste0(prefix, ".", name, ".std_error"), cf[i, 2])
    out(paste0(prefix, ".", name, ".t"), cf[i, 3])
    out(paste0(prefix, ".", name, ".p"), cf[i, 4])
    if (i > 1) out(paste0(prefix, ".", name, ".vif"), v[[name]])
  }
  r <- rstandard(f)
  out(paste0(prefix, ".rstandard.1"), r[[1]])
  out(paste0(prefix, ".rstandard.max_abs"), max(abs(r)))
  m2 <- mean((e - mean(e))^2)
  out(paste0(prefix, ".skewness"), mean((e - mean(e))^3) / m2^1.5)
  out(paste0(prefix, ".excess_kurtosis"), mean((e - mean(e))^4) / m2^2 - 3)
  gq <- lmtest::gqtest(f, fraction = 0.2, order.by = fitted(f))
  out(paste0(prefix, ".gq"), gq$statistic)
  out(paste0(prefix, ".gq_p"), gq$p.value)
}

# Backward elimination: while any VIF >= 5 drop, among those, the term with
# the largest p; otherwise while any p >= 0.05 drop the largest p.
eliminate <- function(data, terms, response) {
  repeat {
    if (length(terms) == 0) return(terms)
    f <- fit_terms(data, terms, response)
    p <- coef(summary(f))[-1, 4]
    names(p) <- terms
    v <- if (length(terms) > 1) car::vif(f) else setNames(1, terms)
    collinear <- terms[v >= 5]
    if (length(collinear) > 0) {
      drop <- collinear[which.max(p[collinear])]
    } else if (max(p) >= 0.05) {
      drop <- terms[which.max(p)]
    } else {
      return(terms)
    }
    terms <- setdiff(terms, drop)
  }
}

# Outliers: while any |standardized residual| > 3, drop the (up to) three
# largest and refit.
remove_outliers <- function(data, terms, response) {
  removed <- 0; steps <- 0
  repeat {
    f <- fit_terms(data, terms, response)
    r <- abs(rstandard(f))
    over <- which(r > 3)
    if (length(over) == 0) break
    drop <- over[order(-r[over])][seq_len(min(3, length(over)))]
    data <- data[-drop, ]
    removed <- removed + length(drop); steps <- steps + 1
  }
  list(data = data, removed = removed, steps = steps)
}

select_model <- function(data, response) {
  terms <- sensors
  removed <- 0; steps <- 0
  repeat {
    terms <- eliminate(data, terms, response)
    o <- remove_outliers(data, terms, response)
    data <- o$data; removed <- removed + o$removed; steps <- steps + o$steps
    again <- eliminate(data, terms, response)
    if (identical(again, terms)) break
    terms <- again
  }
  list(terms = terms, data = data, removed = removed, steps = steps)
}

loro_rmse <- function(data, terms, response) {
  e <- c()
  for (run in unique(data$run)) {
    train <- data[data$run != run, ]
    test <- data[data$run == run, ]
    f <- fit_terms(train, terms, response)
    e <- c(e, test[[response]] - predict(f, test))
  }
  sqrt(mean(e^2))
}

# 1. Full model, all eight sensors, all 623 points.
full <- fit_terms(d, sensors, "dy_mm")
dump_fit("full", full, sensors)
out("full.loro_rmse", loro_rmse(d, sensors, "dy_mm"))

# 2. The selection procedure of docs/model.md section 4 (Y axis).
sel <- select_model(d, "dy_mm")
cat(sprintf("selected.terms %s\n", paste(sel$terms, collapse = ",")))
out("selected.removed_outliers", sel$removed)
out("selected.outlier_steps", sel$steps)
dump_fit("selected", fit_terms(sel$data, sel$terms, "dy_mm"), sel$terms)
out("selected.loro_rmse", loro_rmse(sel$data, sel$terms, "dy_mm"))

# 3. A small two-term model for a rank and VIF check with few predictors.
small <- fit_terms(d, c("dT_x1", "dT_y2"), "dy_mm")
dump_fit("small", small, c("dT_x1", "dT_y2"))
