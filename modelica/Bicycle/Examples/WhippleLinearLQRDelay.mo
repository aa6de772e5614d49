within Bicycle.Examples;
model WhippleLinearLQRDelay "Benchmark bicycle at 3 m/s (weave-unstable) stabilized by an LQR autopilot acting through a 0.1 s rider delay"
  extends Bicycle.Icons.Example;
  Bicycle.Bicycles.WhippleLinear bike(v = 3) "Linear Whipple bicycle with the benchmark parameters, weave-unstable at 3 m/s"
    annotation(Placement(transformation(extent = {{30, -40}, {110, 40}})));
  Bicycle.Control.StateFeedback autopilot(
    K1 = -27.877794943557305,
    K2 = 18.21930493503048,
    K3 = -7.030319966648618,
    K4 = 1.9189718694862468) "LQR state feedback designed on the benchmark bicycle at 3 m/s (weights 10, 1, 0.1 and r = 0.1)"
    annotation(Placement(transformation(extent = {{-110, -4}, {-70, 36}})));
  Bicycle.Rider.PadeDelay delay(tau = 0.1, n = 2) "Neuromuscular delay of the steer torque, second-order Pade approximation"
    annotation(Placement(transformation(extent = {{-40, -4}, {0, 36}})));
  Bicycle.Sources.TorquePulse push(amplitude = 20, start = 0.5, duration = 0.2) "Lateral push: a roll torque of 20 N.m for 0.2 s"
    annotation(Placement(transformation(extent = {{-40, -60}, {0, -20}})));
equation
  connect(bike.phi, autopilot.phi) annotation(Line(points = {{114, 30}, {122, 30}, {122, 64}, {-122, 64}, {-122, 28}, {-114, 28}}, color = {0, 0, 127}));
  connect(bike.delta, autopilot.delta) annotation(Line(points = {{114, 18}, {128, 18}, {128, 70}, {-128, 70}, {-128, 20}, {-114, 20}}, color = {0, 0, 127}));
  connect(bike.phi_dot, autopilot.phi_dot) annotation(Line(points = {{114, 6}, {134, 6}, {134, 76}, {-134, 76}, {-134, 12}, {-114, 12}}, color = {0, 0, 127}));
  connect(bike.delta_dot, autopilot.delta_dot) annotation(Line(points = {{114, -6}, {140, -6}, {140, 82}, {-140, 82}, {-140, 4}, {-114, 4}}, color = {0, 0, 127}));
  connect(autopilot.T, delay.u) annotation(Line(points = {{-68, 16}, {-44, 16}}, color = {0, 0, 127}));
  connect(delay.y, bike.T_delta) annotation(Line(points = {{2, 16}, {22, 16}}, color = {0, 0, 127}));
  connect(push.y, bike.T_phi) annotation(Line(points = {{2, -40}, {12, -40}, {12, -16}, {22, -16}}, color = {0, 0, 127}));
  annotation(
    Diagram(coordinateSystem(extent = {{-160, -80}, {160, 100}})),
    experiment(StartTime = 0, StopTime = 10, Tolerance = 1e-8, Interval = 0.01),
    Documentation(info = "<html>
<p>The system <code>cosim/systems/lqr-autopilot.toml</code> as one Modelica model, with the
Modelica twins that <code>cosim ssp</code> exports for its Python blocks: the LQR design becomes
<code>StateFeedback</code> with the designed gains (python-control's <code>lqr</code> on the
analytic linear benchmark bicycle at 3 m/s, Q = diag(10, 1, 0.1, 0.1), R = 0.1; see
<code>cosim.cosimulation.controllers.lqr_gains</code>), the exact transport delay of 0.1 s becomes
its second-order Pade approximation. The four measured states go to the autopilot, its torque
through the delay to the steer input; a push on the roll input excites the bicycle, and the
loop brings it back upright.</p>
</html>"));
end WhippleLinearLQRDelay;
