within Bicycle.Examples;
model InvertedPendulumSteerFeedback "Inverted-pendulum bicycle (1) balanced by proportional steering delta = -k2*phi (5), from an initial lean"
  extends Bicycle.Icons.Example;
  parameter Real k2(unit = "1", min = 0) = 0.8 "Gain k2 from roll angle to steer angle (stable iff k2 > b*g/V^2 = 0.39 at 5 m/s, eq (6))";
  Bicycle.Bicycles.InvertedPendulum bicycle(V = 5, frame(phi(start = 0.05))) "Bicycle at 5 m/s, initial lean 0.05 rad"
    annotation(Placement(transformation(extent = {{0, -55}, {80, 25}})));
  Bicycle.Control.SteerAngleFeedback controller(k2 = k2) "Rider steering into the lean, delta = -k2*phi"
    annotation(Placement(transformation(extent = {{-80, -35}, {-40, 5}})));
equation
  connect(bicycle.phi, controller.phi) annotation(Line(points = {{84, 9}, {92, 9}, {92, 55}, {-92, 55}, {-92, -15}, {-84, -15}}, color = {0, 0, 127}));
  connect(controller.delta, bicycle.delta) annotation(Line(points = {{-38, -15}, {-8, -15}}, color = {0, 0, 127}));
  annotation(
    experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-8, Interval = 0.01),
    Documentation(info = "<html>
<p>Closed loop (6): <code>J*der(phi,2) + D*V*k2/b*der(phi) + (m*V^2*h*k2/b - m*g*h)*phi = 0</code>.
With k2 = 0.8 &gt; b*g/V^2 = 0.39 the lean of 0.05 rad decays (damped oscillation); below
0.39 the bicycle falls. The bicycle steers into the lean and its path deviates to the right.</p>
<p>The loop is closed by connecting the bicycle's roll-angle output to the controller and the
controller's steer-angle output to the bicycle: the same wiring as a co-simulation of the
bicycle's FMU with the Python block <code>SteerAngleFeedback</code> (or the FMU of
<code>Bicycle.Control.SteerAngleFeedback</code>).</p>
</html>"));
end InvertedPendulumSteerFeedback;
