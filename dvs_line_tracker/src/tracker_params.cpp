#include <dvs_line_tracker/tracker_params.h>

#include <yaml-cpp/yaml.h>

#include <stdexcept>

namespace dvs_line_tracker
{
void forEachParam(LineTrackerParams& p, const std::function<void(const ParamRef&)>& visit)
{
  auto d = [&](const char* name, double& v, const char* unit) { visit(ParamRef{name, &v, nullptr, nullptr, unit}); };
  auto i = [&](const char* name, int& v, const char* unit) { visit(ParamRef{name, nullptr, &v, nullptr, unit}); };
  auto b = [&](const char* name, bool& v) { visit(ParamRef{name, nullptr, nullptr, &v, ""}); };
  // Initialisation (thesis 4.2.1).
  d("hough_angle_bin_deg", p.hough.angle_bin_deg, "deg");
  d("hough_radius_bin_px", p.hough.radius_bin_px, "px");
  i("hough_threshold", p.hough.vote_threshold, "events");
  d("hough_attribution_distance_px", p.hough.attribution_distance_px, "px");
  d("segment_max_gap_px", p.hough.max_gap_px, "px");
  d("segment_min_length_px", p.hough.min_segment_length_px, "px");
  i("segment_min_events", p.hough.min_segment_events, "events");
  i("init_window_events", p.hough.window_events, "events");
  b("init_unique_pixels", p.hough.unique_pixels);
  b("init_neighbour_filter", p.hough.neighbour_filter);
  i("init_neighbour_filter_events", p.hough.neighbour_filter_events, "events");
  i("init_neighbour_filter_min", p.hough.neighbour_filter_min, "pixels");
  i("init_check_interval", p.init_check_interval, "events");
  d("init_min_check_period", p.init_min_check_period_s, "s");
  i("init_min_events", p.init_min_events, "events");
  i("init_refine_events", p.init_refine_events, "events");
  d("init_min_coverage", p.init_min_coverage, "");
  d("init_border_margin_px", p.init_border_margin_px, "px");
  d("init_max_inside_ratio", p.init_max_inside_ratio, "");
  i("init_confirmations", p.init_confirmations, "");
  d("init_confirm_position_ratio", p.init_confirm_position_ratio, "");
  d("init_confirm_angle_deg", p.init_confirm_angle_deg, "deg");
  d("polygon_min_angle_deg", p.polygon.min_turn_angle_deg, "deg");
  d("polygon_max_angle_deg", p.polygon.max_turn_angle_deg, "deg");
  d("polygon_corner_proximity_ratio", p.polygon.corner_proximity_ratio, "");
  d("polygon_min_side_px", p.polygon.min_side_px, "px");
  d("init_max_reprojection_px", p.init.max_reprojection_rms_px, "px");
  b("init_refine", p.init.refine);
  // Tracking (thesis 4.2.2).
  d("max_orthogonal_distance_px", p.attribution.max_orthogonal_px, "px");
  d("max_parallel_distance_px", p.attribution.max_parallel_px, "px");
  b("edge_run_model", p.edge_run_model);
  d("contrast_threshold", p.contrast_threshold, "log intensity");
  d("contrast_threshold_prior", p.contrast_threshold_prior, "log intensity");
  i("contrast_learning_runs", p.contrast_learning_runs, "runs");
  d("edge_contrast_ratio", p.edge_contrast_ratio, "");
  d("edge_offset_px", p.edge_offset_px, "px");
  d("buffer_motion_px", p.buffer_motion_px, "px");
  i("buffer_size", p.buffer_size, "events");
  i("full_iterations", p.estimator.full_iterations, "");
  i("extra_relinearizations", p.estimator.extra_relinearizations, "");
  d("damping", p.estimator.damping, "");
  d("damping_partial_view", p.damping_partial_view, "");
  d("huber_px", p.estimator.huber_px, "px");
  // Quality monitoring.
  i("quality_check_interval", p.quality_check_interval, "events");
  i("min_visible_segments", p.min_visible_segments, "");
  d("min_visible_length_px", p.min_visible_length_px, "px");
  d("max_mean_residual_px", p.max_mean_residual_px, "px");
  d("min_attributed_ratio", p.min_attributed_ratio, "");
  d("min_depth", p.min_depth_m, "m");
}

bool parseSolverType(const std::string& name, SolverType& type)
{
  if (name == "incremental")
    type = SolverType::kIncremental;
  else if (name == "full")
    type = SolverType::kFullGaussNewton;
  else
    return false;
  return true;
}

const char* solverTypeName(SolverType type)
{
  return type == SolverType::kIncremental ? "incremental" : "full";
}

void loadTrackerParamsYaml(const std::string& path, LineTrackerParams& params)
{
  YAML::Node root;
  try
  {
    root = YAML::LoadFile(path);
  }
  catch (const YAML::Exception& e)
  {
    throw std::runtime_error("cannot read parameter file '" + path + "': " + e.what());
  }
  if (root.IsNull())
    return;
  if (!root.IsMap())
    throw std::runtime_error(path + ": expected a mapping of parameter names to values");
  for (const auto& kv : root)
  {
    const std::string key = kv.first.as<std::string>();
    if (key == "solver")
    {
      if (!parseSolverType(kv.second.as<std::string>(), params.estimator.solver))
        throw std::runtime_error(path + ": solver must be 'incremental' or 'full'");
      continue;
    }
    bool found = false;
    forEachParam(params, [&](const ParamRef& r) {
      if (key != r.name)
        return;
      found = true;
      try
      {
        if (r.d)
          *r.d = kv.second.as<double>();
        else if (r.i)
          *r.i = kv.second.as<int>();
        else
          *r.b = kv.second.as<bool>();
      }
      catch (const YAML::Exception&)
      {
        throw std::runtime_error(path + ": parameter '" + key + "' has the wrong type");
      }
    });
    if (!found)
      throw std::runtime_error(path + ": unknown parameter '" + key + "'");
  }
  const std::string err = validateParams(params);
  if (!err.empty())
    throw std::runtime_error(path + ": " + err);
}
}  // namespace dvs_line_tracker
