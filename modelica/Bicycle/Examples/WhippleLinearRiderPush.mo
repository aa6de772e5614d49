within Bicycle.Examples;
model WhippleLinearRiderPush "Benchmark bicycle at 4 m/s, below its weave speed, balanced by the rider's proportional steer torque after a lateral push"
  extends Bicycle.Icons.Example;
  Bicycle.Bicycles.WhippleLinear bike(v = 4) "Linear Whipple bicycle with the benchmark parameters, not self-stable at 4 m/s"
    annotation(Placement(transformation(extent = {{0, -55}, {80, 25}})));
  Bicycle.Control.Proportional rider(k = 2) "The paper's rider, T = -k*phi"
    annotation(Placement(transformation(extent = {{-80, -19}, {-40, 21}})));
  Bicycle.Sources.TorquePulse push(amplitude = 10, start = 0.5, duration = 0.2) "Lateral push: a roll torque of 10 N.m for 0.2 s"
    annotation(Placement(transformation(extent = {{-80, -90}, {-40, -50}})));
equation
  connect(bike.phi, rider.phi) annotation(Line(points = {{84, 15}, {92, 15}, {92, 55}, {-92, 55}, {-92, 1}, {-84, 1}}, color = {0, 0, 127}));
  connect(rider.T, bike.T_delta) annotation(Line(points = {{-38, 1}, {-8, 1}}, color = {0, 0, 127}));
  connect(push.y, bike.T_phi) annotation(Line(points = {{-38, -70}, {-24, -70}, {-24, -31}, {-8, -31}}, color = {0, 0, 127}));
  annotation(
    experiment(StartTime = 0, StopTime = 20, Tolerance = 1e-8, Interval = 0.01),
    Documentation(info = "<html>
<p>The system <code>cosim/systems/rider-p-control.toml</code> as one Modelica model: the same three
blocks with the same parameters and the same connections
(<code>bike.phi -&gt; rider.phi</code>, <code>rider.T -&gt; bike.T_delta</code>,
<code>push.y -&gt; bike.T_phi</code>). At 4 m/s the benchmark bicycle is below its weave speed
(4.29 m/s); the rider's gain k = 2 N.m/rad stabilizes it (slowest closed-loop pole -0.10 1/s) and
the lean the push causes dies out.</p>
<p>Here the loop is closed in continuous time. The co-simulation of the system file holds the
rider's torque over each communication step; it converges to this model at first order in the
step.</p>
</html>"));
end WhippleLinearRiderPush;
