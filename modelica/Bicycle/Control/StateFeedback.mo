within Bicycle.Control;
block StateFeedback "State feedback on steer torque (LQR autopilot): T = -(K1*phi + K2*delta + K3*phi_dot + K4*delta_dot)"
  parameter Real K1(unit = "N.m/rad") = 0 "Gain on roll angle";
  parameter Real K2(unit = "N.m/rad") = 0 "Gain on steer angle";
  parameter Real K3(unit = "N.m.s/rad") = 0 "Gain on roll rate";
  parameter Real K4(unit = "N.m.s/rad") = 0 "Gain on steer rate";
  input Bicycle.Units.Angle phi "Roll angle";
  input Bicycle.Units.Angle delta "Steer angle";
  input Bicycle.Units.AngularVelocity phi_dot "Roll rate";
  input Bicycle.Units.AngularVelocity delta_dot "Steer rate";
  output Bicycle.Units.Torque T "Steer torque";
equation
  T = -(K1*phi + K2*delta + K3*phi_dot + K4*delta_dot);
  annotation(__Cosim(export = true));
end StateFeedback;
