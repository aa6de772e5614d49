within Bicycle.Components;
model StaticFrontFork "Front fork with static torque balance about the steer axis, eqs (7)-(13)"
  parameter Bicycle.Units.Mass m = 92 "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length a = 0.5 "Horizontal distance a from the rear contact point P1 to the centre of mass";
  parameter Bicycle.Units.Length b = 1.0 "Wheel base b";
  parameter Bicycle.Units.Length c = 0.08 "Trail c";
  parameter Bicycle.Units.Angle lambda = 1.2217304763960306 "Head angle lambda";
  parameter Bicycle.Units.Velocity V = 5 "Forward speed V";
  parameter Bicycle.Units.Acceleration g = 9.81 "Gravitational acceleration";
  Bicycle.Interfaces.Roll roll "Roll axis (the fork reads the frame roll angle)";
  Bicycle.Interfaces.Steer steer "Steer axis";
protected
  Real N_f(unit = "N") "Vertical contact force on the front wheel";
  Real F_f(unit = "N") "Lateral contact force on the front wheel";
  Bicycle.Units.Angle phi_f "Roll angle of the front fork plane, eq (7)";
equation
  N_f = a*m*g/b;
  F_f = a*m*V^2*sin(lambda)/b^2*steer.delta;
  phi_f = roll.phi - steer.delta*cos(lambda);
  // Torque of the ground contact forces about the steer axis; the handlebar torque balances it.
  steer.tau = (F_f + N_f*phi_f)*c*sin(lambda);
  roll.tau = 0;
end StaticFrontFork;
