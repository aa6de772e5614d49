within Bicycle.Control;
block PD "Proportional-derivative rider: T = -kp*phi - kd*phi_dot"
  parameter Real kp(unit = "N.m/rad") = 10 "Gain from roll angle to steer torque";
  parameter Real kd(unit = "N.m.s/rad") = 1 "Gain from roll rate to steer torque";
  input Bicycle.Units.Angle phi "Roll angle";
  input Bicycle.Units.AngularVelocity phi_dot "Roll rate";
  output Bicycle.Units.Torque T "Steer torque";
equation
  T = -kp*phi - kd*phi_dot;
  annotation(__Cosim(export = true));
end PD;
