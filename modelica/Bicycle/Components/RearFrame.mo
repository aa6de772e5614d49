within Bicycle.Components;
model RearFrame "Rear frame with rigidly attached rider and wheels: roll momentum balance, eqs (1) and (14)"
  parameter Bicycle.Units.Mass m = 92 "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length a = 0.5 "Horizontal distance a from the rear contact point P1 to the centre of mass";
  parameter Bicycle.Units.Length h = 1.0 "Height h of the centre of mass above the ground";
  parameter Bicycle.Units.Length b = 1.0 "Wheel base b";
  parameter Bicycle.Units.Length c = 0.08 "Trail c";
  parameter Bicycle.Units.Angle lambda = 1.2217304763960306 "Head angle lambda (70 deg; 90 deg is a vertical steer axis)";
  parameter Bicycle.Units.MomentOfInertia J = 96.7 "Moment of inertia J about the x axis";
  parameter Bicycle.Units.MomentOfInertia D = 46.3 "Inertia product D = -Jxz with respect to the x and z axes";
  parameter Bicycle.Units.Velocity V = 5 "Forward speed V of the rear contact point";
  parameter Bicycle.Units.Acceleration g = 9.81 "Gravitational acceleration";
  Bicycle.Units.Angle phi(start = 0, fixed = true) "Roll angle, positive leaning to the right";
  Bicycle.Units.AngularMomentum L(start = 0, fixed = true) "Angular momentum about the x axis, L = J*der(phi) - D*V*sin(lambda)*delta/b";
  Bicycle.Units.AngularVelocity omega "Roll rate der(phi)";
  Bicycle.Interfaces.Roll roll "Roll axis";
  Bicycle.Interfaces.Steer steer "Steer axis (the frame reads the steer angle)";
equation
  // Momentum form of (14): the steer angle of a static fork is algebraic, so der(delta) must not appear.
  omega = (L + D*V*sin(lambda)*steer.delta/b)/J;
  der(phi) = omega;
  der(L) = m*g*h*phi + m*(V^2*h - a*c*g)*sin(lambda)/b*steer.delta + roll.tau;
  roll.phi = phi;
  steer.tau = 0;
  annotation(Documentation(info = "<html>
<p>Angular momentum balance of the rear frame about the x axis. With <code>lambda = 90 deg</code> and
<code>c = 0</code> it is the inverted-pendulum model (1); otherwise (14), where the steer angle enters
as the effective front-wheel angle <code>delta*sin(lambda)</code>.</p>
</html>"));
end RearFrame;
