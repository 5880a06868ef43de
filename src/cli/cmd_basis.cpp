#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "brdf/basis.h"
#include "brdf/basis_file.h"
#include "brdf/directions.h"
#include "brdf/evaluation.h"
#include "cli/args.h"
#include "cli/commands.h"
#include "cli/held_out.h"
#include "core/error.h"

namespace acq::cli {
int BasisBuild(const Argv& argv) {
  const Args args("acq basis build", argv,
                  {"o", "output", "components", "holdout-every", "holdout-offset", "holdout"},
                  {"quiet"});
  const std::string out = args.Has("o") ? args.Get("o") : args.Required("output");
  HoldOut hold_out;
  hold_out.every = args.GetInt("holdout-every", 0, 0, 100000);
  hold_out.offset = args.GetInt("holdout-offset", 0, 0, 100000);
  hold_out.names = args.All("holdout");
  BasisOptions options;
  options.components = args.GetInt("components", options.components, 1, 1024);
  options.progress = !args.Has("quiet");
  const MaterialSplit split = SplitMaterials(ListMaterials(args.positionals()), hold_out);
  options.Check(int(3 * split.training.size()));

  const auto start = std::chrono::steady_clock::now();
  const BasisData basis = BuildBasis(split, options);
  WriteBasisFile(basis.View(), out);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  double total = 0, kept = 0;
  for (int i = 0; i < basis.training_rows; ++i) {
    const double v = basis.singular_values[i] * basis.singular_values[i];
    total += v;
    if (i < basis.components) kept += v;
  }
  std::printf("basis: %zu training materials (%d rows), %zu held out, %d components\n",
              split.training.size(), basis.training_rows, split.held_out.size(), basis.components);
  std::printf("basis: variance explained by the stored components: %.4f\n",
              total > 0 ? kept / total : 0.0);
  std::printf("basis: wrote %s in %.1f s\n", out.c_str(), seconds);
  return 0;
}

int BasisInfo(const Argv& argv) {
  const Args args("acq basis info", argv, {}, {"no-verify"});
  if (args.positionals().size() != 1)
    throw UserError("acq basis info", "expected one basis file", "acq basis info BASIS");
  const std::string path = args.positionals()[0];
  const MappedBasis basis = MappedBasis::Open(path, !args.Has("no-verify"));
  const BasisView& v = basis.View();
  std::printf("file: %s (%zu bytes, format version %u, crc32 %08x%s)\n", path.c_str(),
              basis.FileBytes(), basis.Version(), basis.Checksum(),
              args.Has("no-verify") ? ", not verified" : ", verified");
  std::printf("components: %d of %d training rows\nsingular values:", v.components,
              v.training_rows);
  for (int i = 0; i < std::min(v.components, 10); ++i) std::printf(" %.4g", v.singular_values[i]);
  std::printf("%s\nsettings:\n%.*s", v.components > 10 ? " ..." : "", int(v.settings.size()),
              v.settings.data());
  return 0;
}

int BasisEval(const Argv& argv) {
  const Args args("acq basis eval", argv, {"basis", "directions", "k", "eta", "write-recon", "csv"},
                  {"all-given"});
  const std::string basis_path = args.Required("basis");
  const MappedBasis mapped = MappedBasis::Open(basis_path);
  const BasisView& basis = mapped.View();
  RidgeOptions ridge;
  ridge.components = args.GetInt("k", ridge.components, 1, 1024);
  ridge.eta = args.GetDouble("eta", ridge.eta, 0, 1e12);
  ridge.Check(basis);
  const std::vector<Direction> directions = ReadDirectionsTsv(args.Required("directions"));
  const std::vector<std::size_t> bins = BinsOf(directions);

  std::vector<MaterialFile> materials = SelectHeldOut(basis, basis_path, args, "acq basis eval");

  const std::string recon_dir = args.Get("write-recon");
  if (!recon_dir.empty()) std::filesystem::create_directories(recon_dir);
  std::vector<std::array<ChannelError, 3>> results(materials.size());
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic)
  for (int i = 0; i < int(materials.size()); ++i) {
    try {
      const MerlBrdf truth = LoadMaterial(materials[i]);
      MerlBrdf recon;
      results[i] =
          EvaluateHomogeneous(basis, truth, bins, ridge, recon_dir.empty() ? nullptr : &recon);
      if (!recon_dir.empty())
        WriteMerlBinary(recon, recon_dir + "/" + materials[i].name + ".binary");
    } catch (...) {
#pragma omp critical
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);

  std::printf("directions: %s (%zu), k = %d, eta = %g, basis %s\n", args.Get("directions").c_str(),
              directions.size(), ridge.components, ridge.eta, basis_path.c_str());
  std::printf("%-28s %8s %8s %8s   %8s %8s %8s\n", "material", "logR", "logG", "logB", "relR",
              "relG", "relB");
  std::vector<double> log_all, rel_all;
  for (std::size_t i = 0; i < materials.size(); ++i) {
    const auto& r = results[i];
    std::printf("%-28s %8.4f %8.4f %8.4f   %8.4f %8.4f %8.4f\n", materials[i].name.c_str(),
                r[0].log_rmse, r[1].log_rmse, r[2].log_rmse, r[0].relative_rmse, r[1].relative_rmse,
                r[2].relative_rmse);
    for (const auto& c : r) {
      log_all.push_back(c.log_rmse);
      rel_all.push_back(c.relative_rmse);
    }
  }
  const double condition = results.empty() ? 0 : results[0][0].condition;
  std::printf("condition number of the sampled rows (k = %d): %.4g\n", ridge.components, condition);
  std::printf("median log-space RMSE over %zu channels: %.4f\n", log_all.size(), Median(log_all));
  std::printf("median relative RMSE (cos-weighted) over %zu channels: %.4f\n", rel_all.size(),
              Median(rel_all));
  if (!(condition < kConditionWarning))
    std::fprintf(stderr,
                 "warning: condition number %.3g of the sampled rows exceeds %.0f: the directions "
                 "are too few or too close together for k = %d, and noise in the observations "
                 "will be amplified; use more or better-spread directions, a smaller --k, or a "
                 "larger --eta\n",
                 condition, kConditionWarning, ridge.components);

  if (args.Has("csv")) {
    std::ofstream csv(args.Get("csv"));
    if (!csv) throw UserError(args.Get("csv"), "cannot create file");
    csv << "material,channel,log_rmse,relative_rmse,condition\n";
    for (std::size_t i = 0; i < materials.size(); ++i)
      for (int c = 0; c < 3; ++c)
        csv << materials[i].name << ","
            << "RGB"[c] << "," << results[i][c].log_rmse << "," << results[i][c].relative_rmse
            << "," << results[i][c].condition << "\n";
  }
  return 0;
}

}  // namespace acq::cli
