within Bicycle.Control;
block PID "PID rider: T = -kp*phi - ki*(integral of phi) - kd*phi_dot"
  parameter Real kp(unit = "N.m/rad") = 10 "Gain from roll angle to steer torque";
  parameter Real ki(unit = "N.m/(rad.s)") = 1 "Gain from the integral of the roll angle to steer torque";
  parameter Real kd(unit = "N.m.s/rad") = 1 "Gain from roll rate to steer torque";
  input Bicycle.Units.Angle phi "Roll angle";
  input Bicycle.Units.AngularVelocity phi_dot "Roll rate";
  output Bicycle.Units.Torque T "Steer torque";
  Real phi_int(unit = "rad.s", start = 0, fixed = true) "Integral of the roll angle";
equation
  der(phi_int) = phi;
  T = -kp*phi - ki*phi_int - kd*phi_dot;
  annotation(__Cosim(export = true));
end PID;
