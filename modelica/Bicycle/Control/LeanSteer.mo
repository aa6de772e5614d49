within Bicycle.Control;
block LeanSteer "Rider using steer torque and upper-body lean: T = -k*phi - kd*phi_dot, theta = -k_lean*phi"
  parameter Real k(unit = "N.m/rad") = 10 "Steer torque per radian of roll";
  parameter Real kd(unit = "N.m.s/rad") = 1 "Steer torque per rad/s of roll rate";
  parameter Real k_lean(unit = "1") = 0.5 "Upper-body lean per radian of roll";
  input Bicycle.Units.Angle phi "Roll angle";
  input Bicycle.Units.AngularVelocity phi_dot "Roll rate";
  output Bicycle.Units.Torque T "Steer torque";
  output Bicycle.Units.Angle theta "Upper-body lean angle relative to the frame";
equation
  T = -k*phi - kd*phi_dot;
  theta = -k_lean*phi;
  annotation(__Cosim(export = true));
end LeanSteer;
