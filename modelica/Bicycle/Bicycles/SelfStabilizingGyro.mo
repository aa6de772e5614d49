within Bicycle.Bicycles;
model SelfStabilizingGyro "Rear frame (14) with a front fork that includes the gyroscopic derivative term: delta = k1*T - k2*phi - k3*der(phi)"
  extends Bicycle.Icons.Bike;
  parameter Bicycle.Units.Mass m(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length a(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.a "Horizontal distance a from the rear contact point to the centre of mass";
  parameter Bicycle.Units.Length h(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.h "Height h of the centre of mass";
  parameter Bicycle.Units.Length b(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.b "Wheel base b";
  parameter Bicycle.Units.Length c(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.c "Trail c";
  parameter Bicycle.Units.Angle lambda(min = 1e-6, max = 1.5707963267948966) = Bicycle.Records.Astrom2005SecondOrder.lambda "Head angle lambda (70 deg)";
  parameter Bicycle.Units.MomentOfInertia J(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.J "Moment of inertia J about the x axis";
  parameter Bicycle.Units.MomentOfInertia D(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.D "Inertia product D = -Jxz";
  parameter Bicycle.Units.Velocity V = Bicycle.Records.Astrom2005SecondOrder.V "Forward speed V";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.g "Gravitational acceleration";
  parameter Bicycle.Units.Time k3(min = 0) = Bicycle.Records.Astrom2005SecondOrder.k3 "Gain k3 of the gyroscopic derivative feedback from roll rate to steer angle";
  Bicycle.Interfaces.RealInput T(final quantity = "Torque", final unit = "N.m") "Steer torque applied to the handlebars"
    annotation(Placement(transformation(extent = {{-140, -20}, {-100, 20}})));
  Bicycle.Interfaces.RealOutput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle, positive leaning to the right"
    annotation(Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Bicycle.Interfaces.RealOutput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle, positive steering to the left"
    annotation(Placement(transformation(extent = {{100, 10}, {120, 30}})));
  Bicycle.Interfaces.RealOutput psi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Yaw angle of the rear frame, positive to the left"
    annotation(Placement(transformation(extent = {{100, -30}, {120, -10}})));
  Bicycle.Interfaces.RealOutput eta(final quantity = "Length", final unit = "m") "Path deviation of the rear contact point, positive to the left"
    annotation(Placement(transformation(extent = {{100, -70}, {120, -50}})));
  Bicycle.Components.SecondOrderRearFrame frame(m = m, h = h, b = b, J = J, D = D, V = V, g = g) "Rear frame with rider and wheels, eq (1)"
    annotation(Placement(transformation(extent = {{-70, -40}, {-30, 0}})));
  Bicycle.Components.GyroscopicFrontFork fork(m = m, a = a, b = b, c = c, lambda = lambda, V = V, g = g, k3 = k3) "Front fork with gyroscopic effects"
    annotation(Placement(transformation(extent = {{30, -40}, {70, 0}})));
  Bicycle.Components.SteerTorque handlebar(T = T) "Rider's steer torque"
    annotation(Placement(transformation(extent = {{30, 20}, {70, 60}})));
  Bicycle.Components.PathKinematics path(V = V, b = b) "Yaw angle and path deviation"
    annotation(Placement(transformation(extent = {{-20, 10}, {20, 50}})));
equation
  connect(frame.roll, fork.roll) annotation(Line(points = {{-50, -40}, {-50, -60}, {50, -60}, {50, -40}}, color = {0, 0, 0}));
  connect(frame.rollRate, fork.rollRate) annotation(Line(points = {{-28, -28}, {26, -28}}, color = {0, 0, 127}));
  connect(fork.front, frame.front) annotation(Line(points = {{28, -12}, {-26, -12}}, color = {0, 0, 127}));
  connect(fork.front, path.front) annotation(Line(points = {{28, -12}, {0, -12}, {0, 6}}, color = {0, 0, 127}));
  connect(handlebar.steer, fork.steer) annotation(Line(points = {{50, 20}, {50, 0}}, color = {0, 0, 0}));
  phi = frame.phi;
  delta = fork.steer.delta;
  psi = path.psi;
  eta = path.eta;
  annotation(
    Icon(graphics = {
      Text(extent = {{20, 96}, {100, 56}}, textString = "(14) k3", textColor = {64, 64, 64})}),
    experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-8, Interval = 0.01),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>Section \"Gyroscopic Effects\": the self-stabilizing bicycle (14) with the front fork
<code>delta = k1(V)*T - k2(V)*phi - k3*der(phi)</code>. The derivative term adds damping
<code>e*k2 + f*k3</code> and stiffness to (15) (e = D*V*sin(lambda)/b, f = m*(V^2*h - a*c*g)*sin(lambda)/b):
the characteristic polynomial is <code>(J + e*k3)*s^2 + (e*k2 + f*k3)*s + f*k2 - m*g*h</code>.
k3 = 0 is the model SelfStabilizing. The roll rate that the fork needs comes from the frame
through a signal connector; delta then solves a linear algebraic loop (delta, der(phi)).</p>
</html>"));
end SelfStabilizingGyro;
