#include <dvs_line_tracker/imu_ekf.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <cmath>
#include <cstdio>

namespace dvs_line_tracker
{
namespace
{
/// Exp of a rotation vector as a quaternion.
Eigen::Quaterniond expQ(const Eigen::Vector3d& w)
{
  const double a2 = w.squaredNorm();
  if (a2 < 1e-8)
    return Eigen::Quaterniond(1.0, 0.5 * w.x(), 0.5 * w.y(), 0.5 * w.z()).normalized();
  const double a = std::sqrt(a2);
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, w / a));
}

/// Log of a rotation matrix (rotation vector).
Eigen::Vector3d logR(const Eigen::Matrix3d& R)
{
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

constexpr double kGravity = 9.81;
constexpr double kSeriesTurn2 = 1e-4;  // squared turn [rad^2] up to which cameraIncrement uses its series
}  // namespace

Vector6d cameraIncrementBetween(const Pose& from, const Pose& to)
{
  const Eigen::Matrix3d dR = to.R_camera_world * from.R_camera_world.transpose();
  Vector6d d;
  if (dR.trace() > 3.0 - 1e-4)
  {
    // Per event the rotation is tiny (< 0.6 deg here): the axis from the antisymmetric part,
    // exact to third order in the angle (1e-7 rad at the bound), without trigonometry.
    d.head<3>() = 0.5 * Eigen::Vector3d(dR(2, 1) - dR(1, 2), dR(0, 2) - dR(2, 0), dR(1, 0) - dR(0, 1));
  }
  else
    d.head<3>() = logR(dR);
  d.tail<3>() = to.t_camera_world - dR * from.t_camera_world;
  return d;
}

ImuEkf::ImuEkf(const ImuFusionParams& params, const ImuExtrinsics& extrinsics) : params_(&params), x_(&extrinsics)
{
  R_imu_camera_ = x_->R_camera_imu.transpose();
  p_imu_camera_ = -R_imu_camera_ * x_->p_camera_imu;
  q_.setIdentity();
  p_.setZero();
  v_.setZero();
  bg_.setZero();
  ba_.setZero();
  g_ = x_->gravity_world ? *x_->gravity_world : Eigen::Vector3d(0, 0, -kGravity);
  P_.setZero();
}

void ImuEkf::start(const Pose& T_world_camera, const Eigen::Vector3d& accel, Keep keep)
{
  // R_world_imu = R_world_camera R_camera_imu; the IMU's origin p_world_camera + R_world_camera p_camera_imu.
  const Eigen::Matrix3d R_wc = T_world_camera.R_world_camera();
  const Eigen::Matrix3d R_wi = R_wc * x_->R_camera_imu;
  q_ = Eigen::Quaterniond(R_wi).normalized();
  p_ = T_world_camera.p_world_camera() + R_wc * x_->p_camera_imu;
  v_.setZero();
  if (!started_)
    keep = Keep::kNothing;
  MatrixNd P = MatrixNd::Zero();
  P.block<3, 3>(kP, kP).diagonal().setConstant(0.05 * 0.05);
  P.block<3, 3>(kV, kV).diagonal().setConstant(params_->initial_velocity_sigma * params_->initial_velocity_sigma);
  P.block<3, 3>(kTheta, kTheta).diagonal().setConstant(0.02 * 0.02);
  if (keep == Keep::kNothing)
  {
    bg_.setZero();
    P.block<3, 3>(kBg, kBg).diagonal().setConstant(params_->initial_gyro_bias_sigma * params_->initial_gyro_bias_sigma);
  }
  else
    P.block<3, 3>(kBg, kBg) = P_.block<3, 3>(kBg, kBg);
  if (keep == Keep::kAll)
  {
    P.block<3, 3>(kBa, kBa) = P_.block<3, 3>(kBa, kBa);
    P.block<3, 3>(kG, kG) = P_.block<3, 3>(kG, kG);
  }
  else
  {
    ba_.setZero();
    P.block<3, 3>(kBa, kBa).diagonal().setConstant(params_->initial_accel_bias_sigma * params_->initial_accel_bias_sigma);
    if (x_->gravity_world)
      g_ = *x_->gravity_world;
    else
    {
      // At (near) rest the accelerometer reads -g in IMU axes.
      const double n = accel.norm();
      g_ = n > 1.0 ? Eigen::Vector3d(-(R_wi * accel) * (kGravity / n)) : Eigen::Vector3d(0, 0, -kGravity);
      P.block<3, 3>(kG, kG).diagonal().setConstant(params_->initial_gravity_sigma * params_->initial_gravity_sigma);
    }
  }
  P_ = P;
  started_ = true;
}

void ImuEkf::propagateMean(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, double dt)
{
  if (dt <= 0)
    return;
  if (use_accelerometer_)
  {
    const Eigen::Vector3d a = q_ * (accel - ba_) + g_;
    p_ += v_ * dt + 0.5 * dt * dt * a;
    v_ += a * dt;
  }
  else
    p_ += v_ * dt;
  q_ = q_ * expQ((gyro - bg_) * dt);
  q_.normalize();
}

void ImuEkf::propagateCovariance(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, double dt)
{
  if (dt <= 0)
    return;
  const Eigen::Matrix3d R = q_.toRotationMatrix();
  // F = I + A dt (first order; dt is one IMU sample period) has five 3x3 blocks besides the
  // identity: F P F^T as block row, then block column operations (the dense 18x18 products were
  // a third of the tracker's time with an IMU, BENCHMARKS.md, fortieth session).
  const Eigen::Matrix3d F_v_theta = -R * skew(accel - ba_) * dt, F_v_ba = -R * dt;
  const Eigen::Matrix3d F_theta = expQ(-(gyro - bg_) * dt).toRotationMatrix();
  MatrixNd A = P_;  // F P
  A.middleRows<3>(kP) += dt * P_.middleRows<3>(kV);
  if (use_accelerometer_)
  {
    A.middleRows<3>(kV) += F_v_theta * P_.middleRows<3>(kTheta) + F_v_ba * P_.middleRows<3>(kBa);
    if (!x_->gravity_world)
      A.middleRows<3>(kV) += dt * P_.middleRows<3>(kG);
  }
  A.middleRows<3>(kTheta) = F_theta * P_.middleRows<3>(kTheta) - dt * P_.middleRows<3>(kBg);
  MatrixNd P = A;  // (F P) F^T
  P.middleCols<3>(kP) += dt * A.middleCols<3>(kV);
  if (use_accelerometer_)
  {
    P.middleCols<3>(kV) += A.middleCols<3>(kTheta) * F_v_theta.transpose() + A.middleCols<3>(kBa) * F_v_ba.transpose();
    if (!x_->gravity_world)
      P.middleCols<3>(kV) += dt * A.middleCols<3>(kG);
  }
  P.middleCols<3>(kTheta) = A.middleCols<3>(kTheta) * F_theta.transpose() - dt * A.middleCols<3>(kBg);
  const double gn = params_->gyro_noise_density, an = params_->accel_noise_density;
  const double gw = params_->gyro_random_walk, aw = params_->accel_random_walk;
  const double an_used = use_accelerometer_ ? an : kUnmodelledAccelDensity;
  P.block<3, 3>(kV, kV).diagonal().array() += an_used * an_used * dt;
  P.block<3, 3>(kTheta, kTheta).diagonal().array() += gn * gn * dt;
  P.block<3, 3>(kBg, kBg).diagonal().array() += gw * gw * dt;
  P.block<3, 3>(kBa, kBa).diagonal().array() += aw * aw * dt;
  P_ = 0.5 * (P + P.transpose());
}

void ImuEkf::inject(const VectorNd& dx)
{
  p_ += dx.segment<3>(kP);
  v_ += dx.segment<3>(kV);
  q_ = (q_ * expQ(dx.segment<3>(kTheta))).normalized();
  bg_ += dx.segment<3>(kBg);
  ba_ += dx.segment<3>(kBa);
  if (!x_->gravity_world)
    g_ += dx.segment<3>(kG);
}

double ImuEkf::updateCameraPose(const Pose& measured, const Matrix6d& cov, double gate)
{
  const Pose predicted = cameraPose();
  Vector6d r;
  r.head<3>() = logR(predicted.R_camera_world * measured.R_world_camera());
  r.tail<3>() = measured.p_world_camera() - predicted.p_world_camera();
  Eigen::Matrix<double, ImuEkf::kN, 6> PHt;
  Matrix6d S;
  poseMeasurementProducts(PHt, S);
  S += cov;
  S = 0.5 * (S + S.transpose());
  const Eigen::LLT<Matrix6d> llt(S);
  if (llt.info() != Eigen::Success)
    return std::numeric_limits<double>::infinity();
  const double chi2 = r.dot(llt.solve(r));
  if (!(chi2 <= gate))
    return chi2;
  const Eigen::Matrix<double, ImuEkf::kN, 6> K = llt.solve(PHt.transpose()).transpose();
  inject(K * r);
  // Joseph form (I - K H) P (I - K H)^T + K cov K^T, expanded with P H^T and S = H P H^T + cov:
  // P - C - C^T + K S K^T with C = K (P H^T)^T (two 18x6 products instead of dense 18x18 ones).
  const Eigen::Matrix<double, ImuEkf::kN, 6> KS = K * S;
  const MatrixNd C = K.lazyProduct(PHt.transpose());
  MatrixNd P = P_ - C - C.transpose();
  P.noalias() += KS.lazyProduct(K.transpose());
  if (!x_->gravity_world)
  {
    // |g| = 9.81 (sigma 0.01 m/s^2): a scalar update.
    const double n = g_.norm();
    Eigen::Matrix<double, 1, ImuEkf::kN> h = Eigen::Matrix<double, 1, ImuEkf::kN>::Zero();
    h.segment<3>(kG) = g_.transpose() / n;
    const Eigen::Matrix<double, ImuEkf::kN, 1> Ph = P * h.transpose();
    const double s = h.dot(Ph) + 1e-4;
    const Eigen::Matrix<double, ImuEkf::kN, 1> k = Ph / s;
    inject(k * (kGravity - n));
    P = P - k * Ph.transpose();
  }
  P_ = 0.5 * (P + P.transpose());
  return chi2;
}

Pose ImuEkf::cameraPose() const
{
  const Eigen::Matrix3d R_wi = q_.toRotationMatrix();
  return Pose::fromWorldCamera(R_wi * R_imu_camera_, p_ + R_wi * p_imu_camera_);
}

Vector6d ImuEkf::cameraIncrement(const Eigen::Vector3d& gyro, const Eigen::Vector3d& accel, double from_s,
                                 double to_s, const Eigen::Matrix3d& R_camera_world) const
{
  const double dt = to_s - from_s;
  const Eigen::Vector3d w = gyro - bg_;
  Vector6d d;
  // R_camera_world(to) = R_camera_imu Exp(-w dt) R_imu_camera R_camera_world(from).
  d.head<3>() = -dt * (x_->R_camera_imu * w);
  // The IMU's displacement in the world, as propagateMean over [0, to] minus over [0, from].
  Eigen::Vector3d dp;
  if (use_accelerometer_)
  {
    const Eigen::Vector3d a = q_ * (accel - ba_) + g_;
    dp = (v_ + from_s * a) * dt + (0.5 * dt * dt) * a;
  }
  else
    dp = v_ * dt;
  // t(to) = dR t(from) - R_camera_world(to) (dp + R_world_imu(to) p_ic - R_world_imu(from) p_ic)
  // with dR = Exp(r), r = d.head: the displacement in the camera axes at `from`, turned by dR;
  // the lever arm's turn R_camera_imu (I - Exp(-theta)) p_ic, theta = w dt.
  const Eigen::Vector3d r = d.head<3>(), u = R_camera_world * dp, theta = dt * w;
  if (theta.squaredNorm() < kSeriesTurn2)
  {
    // Between two events: both to second order in the turn (third-order error 2e-7 relative).
    const Eigen::Vector3d r_u = r.cross(u), th_p = theta.cross(p_imu_camera_);
    d.tail<3>() = -(u + r_u + 0.5 * r.cross(r_u)) - x_->R_camera_imu * (th_p - 0.5 * theta.cross(th_p));
  }
  else
  {
    // A long interval (a gap in the IMU's stream, an event-free gap): exact.
    const double a = std::sqrt(theta.squaredNorm());
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(a, theta / a).toRotationMatrix();  // Exp(theta)
    d.tail<3>() = -(x_->R_camera_imu * turn.transpose() * x_->R_camera_imu.transpose() * u) -
                  x_->R_camera_imu * (p_imu_camera_ - turn.transpose() * p_imu_camera_);
  }
  return d;
}

Eigen::Vector3d ImuEkf::cameraAngularVelocity(const Eigen::Vector3d& gyro) const
{
  return x_->R_camera_imu * (gyro - bg_);
}

Eigen::Vector3d ImuEkf::cameraVelocityWorld(const Eigen::Vector3d& gyro) const
{
  return v_ + q_ * (gyro - bg_).cross(p_imu_camera_);
}

void ImuEkf::poseMeasurementProducts(Eigen::Matrix<double, kN, 6>& PHt, Matrix6d& HPHt) const
{
  const Eigen::Matrix3d M = -(q_.toRotationMatrix() * skew(p_imu_camera_));
  PHt.leftCols<3>().noalias() = P_.middleCols<3>(kTheta) * x_->R_camera_imu.transpose();
  PHt.rightCols<3>() = P_.middleCols<3>(kP);
  PHt.rightCols<3>().noalias() += P_.middleCols<3>(kTheta) * M.transpose();
  HPHt.topRows<3>().noalias() = x_->R_camera_imu * PHt.middleRows<3>(kTheta);
  HPHt.bottomRows<3>() = PHt.middleRows<3>(kP);
  HPHt.bottomRows<3>().noalias() += M * PHt.middleRows<3>(kTheta);
}

Matrix6d ImuEkf::cameraPoseCovariance() const
{
  Eigen::Matrix<double, ImuEkf::kN, 6> PHt;
  Matrix6d HPHt;
  poseMeasurementProducts(PHt, HPHt);
  return HPHt;
}

Eigen::Matrix3d ImuEkf::cameraVelocityCovariance() const { return P_.block<3, 3>(kV, kV); }

Eigen::Matrix3d ImuEkf::cameraAngularVelocityCovariance(double sample_period_s) const
{
  const double gn = params_->gyro_noise_density;
  Eigen::Matrix3d c = x_->R_camera_imu * P_.block<3, 3>(kBg, kBg) * x_->R_camera_imu.transpose();
  c.diagonal().array() += gn * gn / std::max(sample_period_s, 1e-6);
  return c;
}
}  // namespace dvs_line_tracker
