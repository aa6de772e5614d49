within Bicycle.Bicycles;
model RearSteered "Rear-wheel steered bicycle (18): model (1) driven backwards, forward speed V > 0 and the rider's signs, steer angle in"
  extends Bicycle.Icons.Bike;
  parameter Bicycle.Units.Mass m(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length h(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.h "Height h of the centre of mass";
  parameter Bicycle.Units.Length b(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.b "Wheel base b";
  parameter Bicycle.Units.MomentOfInertia J(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.J "Moment of inertia J about the x axis";
  parameter Bicycle.Units.MomentOfInertia D(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.D "Inertia product D = -Jxz of model (1), whose x axis points from the unsteered to the steered wheel";
  parameter Bicycle.Units.Velocity V = Bicycle.Records.Astrom2005SecondOrder.V "Forward speed V, positive: the unsteered wheel leads, the steered wheel trails (negative: ridden backwards)";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.g "Gravitational acceleration";
  parameter Bicycle.Units.Angle phi0 = 0 "Initial roll angle phi, positive leaning to the rider's right";
  Bicycle.Interfaces.RealInput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle of the rear wheel (vertical steer axis), positive steering the bicycle to the rider's left"
    annotation(Placement(transformation(extent = {{-140, -20}, {-100, 20}})));
  Bicycle.Interfaces.RealOutput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle, positive leaning to the rider's right"
    annotation(Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Bicycle.Interfaces.RealOutput psi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Yaw angle of the frame, positive turning to the rider's left"
    annotation(Placement(transformation(extent = {{100, -10}, {120, 10}})));
  Bicycle.Interfaces.RealOutput eta(final quantity = "Length", final unit = "m") "Path deviation of the front (unsteered) contact point, positive to the rider's left"
    annotation(Placement(transformation(extent = {{100, -70}, {120, -50}})));
  Bicycle.Components.SecondOrderRearFrame frame(m = m, h = h, b = b, J = J, D = D, V = -V, g = g, phi(start = -phi0)) "Frame with rider and wheels, eq (1) at speed -V in the axes of model (1): roll angle -phi"
    annotation(Placement(transformation(extent = {{-70, -40}, {-30, 0}})));
  Bicycle.Components.SteerAngle handlebar(delta = -delta) "Steer angle of model (1), -delta: counter-clockwise seen from above"
    annotation(Placement(transformation(extent = {{30, -40}, {70, 0}})));
  Bicycle.Components.PathKinematics path(V = -V, b = b) "Yaw angle and path deviation of model (1) at speed -V (deviation -eta)"
    annotation(Placement(transformation(extent = {{-20, 10}, {20, 50}})));
equation
  connect(handlebar.front, frame.front) annotation(Line(points = {{28, -12}, {-26, -12}}, color = {0, 0, 127}));
  connect(handlebar.front, path.front) annotation(Line(points = {{28, -12}, {0, -12}, {0, 6}}, color = {0, 0, 127}));
  // From the axes of model (1) (x from the unsteered to the steered wheel) to the rider's axes
  // (x forward, the direction of motion): a half turn about the vertical. The roll angle and the
  // lateral deviation change sign; yaw and yaw rate keep it; the steer angle of model (1) is the
  // rotation of the steered wheel about the upward axis, -delta.
  phi = -frame.phi;
  psi = path.psi;
  eta = -path.eta;
  annotation(
    Icon(graphics = {
      Text(extent = {{20, 96}, {100, 56}}, textString = "(18)", textColor = {64, 64, 64}),
      Line(points = {{70, 44}, {30, 44}}, color = {255, 0, 0}, thickness = 0.75, arrow = {Arrow.None, Arrow.Filled}, arrowSize = 8)}),
    experiment(StartTime = 0, StopTime = 2, Tolerance = 1e-8, Interval = 0.01),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>Section \"Rear-Wheel Steering\" of the paper: <i>a model for a bicycle with rear-wheel steering is
obtained simply by reversing the sign of the velocity of models with forward-wheel steering</i>.
This model is that construction: the inverted-pendulum bicycle (1) (vertical steer axis, zero
trail) driven backwards at speed <code>-V</code>, seen by a rider who faces the direction of
motion. Its variables are the rider's:</p>
<table border=\"1\" cellpadding=\"3\">
<tr><th>variable</th><th>sign convention (the rider's, ISO 8855: x forward, y left, z up)</th>
<th>in the axes of model (1)</th></tr>
<tr><td><code>V</code></td><td>forward speed, positive: the unsteered wheel leads and the steered
wheel trails</td><td><code>-V</code></td></tr>
<tr><td><code>phi</code></td><td>roll angle, positive leaning to the rider's right</td>
<td><code>frame.phi = -phi</code></td></tr>
<tr><td><code>delta</code></td><td>steer angle, positive when the rider steers the bicycle to the
left (the rear wheel turned clockwise seen from above)</td>
<td><code>handlebar.delta = -delta</code></td></tr>
<tr><td><code>psi</code></td><td>yaw angle, positive turning left</td><td><code>path.psi = psi</code></td></tr>
<tr><td><code>eta</code></td><td>lateral deviation of the front (unsteered) contact point, positive
to the left</td><td><code>path.eta = -eta</code></td></tr>
</table>
<p>The rider's axes are those of model (1) turned half a revolution about the vertical, so the roll
angle and the lateral deviation change sign, the yaw angle does not, and the steer angle (a
rotation about the vertical axis) keeps its geometric sense, which steers the bicycle the other
way because the steered wheel now trails; <code>delta</code> is therefore minus the rotation of the
rear wheel. In these variables the paper's equations hold as printed, with V &gt; 0:</p>
<pre>  J*der(phi,2) - m*g*h*phi = -D*V/b*der(delta) + m*V^2*h/b*delta
  G_phi_delta(s) = (-V*D*s + m*V^2*h)/(b*(J*s^2 - m*g*h))        (18)
  der(psi) = V*delta/b,   der(eta) = V*psi,   G_eta_delta(s) = V^2/(b*s^2)</pre>
<p>(18) has the pole <code>p = sqrt(m*g*h/J)</code> (3.06 1/s for the Table 1 bicycle) and the zero
<code>z = m*V*h/D</code> (9.94 1/s at 5 m/s) in the right half plane; <code>z/p</code> grows with V.
The proportional steering <code>delta = -k2*phi</code> (5) gives (19),
<code>J*der(phi,2) - D*V*k2/b*der(phi) + (m*V^2*h*k2/b - m*g*h)*phi = 0</code>, unstable for every
k2 &gt; 0 and V &gt; 0 (Examples.RearSteeredSteerFeedback).</p>
<p>A negative <code>V</code> rides the rear-steered bicycle backwards: the steered wheel then leads,
and the model is the front-steered bicycle (1) at speed <code>-V</code>, seen by a rider facing
backwards (transfer function (4) at <code>-V</code>).</p>
<p>The states are those of model (1), <code>frame.phi = -phi</code>, <code>frame.L</code>,
<code>path.psi</code>, <code>path.eta = -eta</code>. Set the initial lean with <code>phi0</code> (the
rider's sign), not with <code>frame.phi</code>.</p>
</html>"));
end RearSteered;
