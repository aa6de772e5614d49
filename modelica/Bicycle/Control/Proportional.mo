within Bicycle.Control;
block Proportional "The paper's rider: steer torque proportional to roll, T = -k*phi"
  parameter Real k(unit = "N.m/rad") = 10 "Gain from roll angle to steer torque";
  input Bicycle.Units.Angle phi "Roll angle, positive leaning to the right";
  output Bicycle.Units.Torque T "Steer torque";
equation
  T = -k*phi;
  annotation(__Cosim(export = true));
end Proportional;
