within Bicycle.Control;
block LaneChange "Lane change by counter-steering: lateral error -> heading -> roll demand -> steer torque"
  parameter Bicycle.Units.Position y_ref = 1 "Lateral offset of the new lane (positive to the right)";
  parameter Bicycle.Units.Time t_start = 1 "Time of the lane-change command";
  parameter Real k_y(unit = "rad/m") = 0.1 "Heading demand per metre of lateral error";
  parameter Real k_psi(unit = "1") = 1 "Roll demand per radian of heading error";
  parameter Real kp(unit = "N.m/rad") = 20 "Steer torque per radian of roll error";
  parameter Real kd(unit = "N.m.s/rad") = 10 "Steer torque per rad/s of roll rate";
  input Bicycle.Units.Angle phi "Roll angle (positive leaning right)";
  input Bicycle.Units.AngularVelocity phi_dot "Roll rate";
  input Bicycle.Units.Angle psi "Heading (positive turning right)";
  input Bicycle.Units.Position y "Lateral position (positive to the right)";
  output Bicycle.Units.Torque T "Steer torque (positive steering right)";
protected
  Bicycle.Units.Position y_cmd "Commanded lateral position";
  Bicycle.Units.Angle phi_ref "Roll demand";
equation
  // Stateless: sampled at communication points, so the step of y_cmd needs no event.
  y_cmd = if time >= t_start - 1e-12 then y_ref else 0;
  phi_ref = k_psi*(k_y*(y_cmd - y) - psi);
  T = kp*(phi - phi_ref) + kd*phi_dot;
  annotation(__Cosim(export = true));
end LaneChange;
