within Bicycle.Components;
model StaticFrontFork "Front fork with static torque balance about the steer axis, eqs (7)-(13)"
  extends Bicycle.Icons.FrontFrameIcon;
  parameter Bicycle.Units.Mass m(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length a(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.a "Horizontal distance a from the rear contact point P1 to the centre of mass";
  parameter Bicycle.Units.Length b(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.b "Wheel base b";
  parameter Bicycle.Units.Length c(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.c "Trail c (c = 0, a neutral fork, makes the static torque balance singular)";
  parameter Bicycle.Units.Angle lambda(min = 1e-6, max = 1.5707963267948966) = Bicycle.Records.Astrom2005SecondOrder.lambda "Head angle lambda (90 deg is a vertical steer axis)";
  parameter Bicycle.Units.Velocity V = Bicycle.Records.Astrom2005SecondOrder.V "Forward speed V";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.g "Gravitational acceleration";
  Bicycle.Interfaces.Roll roll "Roll axis (the fork reads the frame roll angle and loads the frame with the torque of its shifted contact point)"
    annotation(Placement(transformation(extent = {{-10, -110}, {10, -90}})));
  Bicycle.Interfaces.Steer steer "Steer axis"
    annotation(Placement(transformation(extent = {{-10, 90}, {10, 110}})));
  Bicycle.Interfaces.EffectiveSteerOutput front "Effective steer angle of the front wheel, delta_f = delta*sin(lambda), eq (8)"
    annotation(Placement(transformation(origin = {-110, 40}, extent = {{-10, -10}, {10, 10}}, rotation = 180)));
protected
  Real N_f(unit = "N") "Vertical contact force on the front wheel";
  Real F_f(unit = "N") "Lateral contact force on the front wheel";
  Bicycle.Units.Angle phi_f "Roll angle of the front fork plane, eq (7)";
equation
  N_f = a*m*g/b;
  F_f = a*m*V^2*sin(lambda)/b^2*steer.delta;
  phi_f = roll.phi - steer.delta*cos(lambda);
  front.delta_f = steer.delta*sin(lambda);
  // Torque of the ground contact forces about the steer axis; the handlebar torque balances it (9).
  steer.tau = (F_f + N_f*phi_f)*c*sin(lambda);
  // The front contact point moves sideways by c*sin(lambda)*delta with the steer angle: the front
  // wheel load N_f there exerts the roll torque T_delta = -m*g*a*c*sin(lambda)*delta/b on the frame.
  roll.tau = N_f*c*sin(lambda)*steer.delta;
  annotation(
    Icon(graphics = {
      Text(extent = {{20, 60}, {100, 20}}, textString = "(11)", textColor = {64, 64, 64})}),
    Documentation(info = "<html>
<p>Static torque balance (9) of the front fork: the handlebar torque <code>T = steer.tau</code>
balances the torque of the lateral and vertical contact forces, so
<code>delta = k1(V)*T - k2(V)*phi</code> (11)-(13). The fork also gives the frame the effective
steer angle <code>delta_f = delta*sin(lambda)</code> (8) and the roll torque
<code>T_delta = -m*g*a*c*sin(lambda)*delta/b</code> of the front wheel load acting at the contact
point displaced by the steer angle; with both, the frame model (1) becomes (14).</p>
<p>Singular at the self-alignment speed <code>V_sa = sqrt(b*g*cot(lambda))</code> (10), where
<code>k1</code> and <code>k2</code> are infinite, and for zero trail.</p>
</html>"));
end StaticFrontFork;
