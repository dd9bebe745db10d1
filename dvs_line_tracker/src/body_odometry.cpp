#include <dvs_line_tracker/body_odometry.h>
#include <dvs_line_tracker/vector_params.h>

namespace dvs_line_tracker
{
namespace
{
/// T_world_body = T_world_camera T_camera_body.
Pose bodyPose(const Pose& T_world_camera, const Pose& T_camera_body)
{
  // Pose stores the inverse (R_camera_world, t_camera_world): here R_body_world, t_body_world.
  Pose b;
  b.R_camera_world = T_camera_body.R_camera_world * T_world_camera.R_camera_world;
  b.t_camera_world = T_camera_body.R_camera_world * T_world_camera.t_camera_world + T_camera_body.t_camera_world;
  return b;
}

/// (rotation error in camera axes, camera position in the world) -> (body position, rotation
/// about the world axes): d p_body = d p_camera - R_world_camera [p_camera_body]x theta_c,
/// theta_world = R_world_camera theta_c.
Matrix6d poseCovarianceToBody(const Matrix6d& cov, const Pose& T_world_camera, const Pose& T_camera_body)
{
  const Eigen::Matrix3d R_wc = T_world_camera.R_world_camera();
  const Eigen::Vector3d p_cb = T_camera_body.p_world_camera();  // the body's origin in the camera frame
  Matrix6d J = Matrix6d::Zero();
  J.block<3, 3>(0, 0) = -R_wc * skew(p_cb);
  J.block<3, 3>(0, 3).setIdentity();
  J.block<3, 3>(3, 0) = R_wc;
  Matrix6d c = J * cov * J.transpose();
  return 0.5 * (c + c.transpose());
}
}  // namespace

std::string parseBodyCameraExtrinsic(const std::string& q_text, const std::string& p_text, Pose& T_camera_body)
{
  // As the suite's pose type, T_camera_body maps camera points into the body frame:
  // p_body = R_body_camera p_camera + p_body_camera.
  return parseRotationTranslation(q_text, "q_body_camera", p_text, "p_body_camera", T_camera_body.R_camera_world,
                                  T_camera_body.t_camera_world);
}

BodyOdometry toBodyOdometry(const ImuOdometry& o, const Pose& T_camera_body)
{
  BodyOdometry b;
  b.t_ns = o.t_ns;
  b.T_world_body = bodyPose(o.T_world_camera, T_camera_body);
  b.pose_covariance = poseCovarianceToBody(o.pose_covariance, o.T_world_camera, T_camera_body);
  // Body velocity: v_body_origin = v_camera + R_world_camera (w_c x p_camera_body), in body axes.
  const Eigen::Matrix3d R_bc = T_camera_body.R_camera_world;  // body <- camera
  const Eigen::Matrix3d R_bw = b.T_world_body.R_camera_world;
  const Eigen::Vector3d p_cb = T_camera_body.p_world_camera();
  const Eigen::Vector3d v_world = o.velocity_world + o.T_world_camera.R_world_camera() * o.angular_velocity_camera.cross(p_cb);
  b.linear_velocity_body = R_bw * v_world;
  b.angular_velocity_body = R_bc * o.angular_velocity_camera;
  b.twist_covariance.block<3, 3>(0, 0) = R_bw * o.velocity_covariance * R_bw.transpose();
  b.twist_covariance.block<3, 3>(3, 3) = R_bc * o.angular_velocity_covariance * R_bc.transpose();
  b.has_twist = true;
  return b;
}

BodyOdometry visionBodyOdometry(int64_t t_ns, const Pose& T_world_camera, const Matrix6d& cov, const Pose& T_camera_body)
{
  BodyOdometry b;
  b.t_ns = t_ns;
  b.T_world_body = bodyPose(T_world_camera, T_camera_body);
  b.pose_covariance = poseCovarianceToBody(cov, T_world_camera, T_camera_body);
  b.twist_covariance.diagonal().setConstant(kUnknownVariance);
  return b;
}
}  // namespace dvs_line_tracker
