within Bicycle.Examples;
model WhippleLinearLQRDelay "Benchmark bicycle at 3 m/s (weave-unstable) stabilized by an LQR autopilot acting through a 0.1 s rider delay"
  Bicycle.Bicycles.WhippleLinear bike(v = 3) "Linear Whipple bicycle with the benchmark parameters, weave-unstable at 3 m/s";
  Bicycle.Control.StateFeedback autopilot(
    K1 = -27.877794943557305,
    K2 = 18.21930493503048,
    K3 = -7.030319966648618,
    K4 = 1.9189718694862468) "LQR state feedback designed on the benchmark bicycle at 3 m/s (weights 10, 1, 0.1 and r = 0.1)";
  Bicycle.Rider.PadeDelay delay(tau = 0.1, n = 2) "Neuromuscular delay of the steer torque, second-order Pade approximation";
  Bicycle.Sources.TorquePulse push(amplitude = 20, start = 0.5, duration = 0.2) "Lateral push: a roll torque of 20 N.m for 0.2 s";
equation
  connect(bike.phi, autopilot.phi);
  connect(bike.delta, autopilot.delta);
  connect(bike.phi_dot, autopilot.phi_dot);
  connect(bike.delta_dot, autopilot.delta_dot);
  connect(autopilot.T, delay.u);
  connect(delay.y, bike.T_delta);
  connect(push.y, bike.T_phi);
  annotation(
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
