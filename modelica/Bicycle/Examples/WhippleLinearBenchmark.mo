within Bicycle.Examples;
model WhippleLinearBenchmark "Benchmark Whipple bicycle at 4.6 m/s released with a roll rate of 0.5 rad/s: the weave oscillation decays (self-stable)"
  extends Bicycle.Icons.Example;
  Bicycle.Bicycles.WhippleLinear bicycle(v = 4.6, phi_dot0 = 0.5, T_phi = 0, T_delta = 0) "Benchmark bicycle of Meijaard et al. (2007), hands off, self-stable for 4.29 m/s < v < 6.02 m/s"
    annotation(Placement(transformation(extent = {{-40, -40}, {40, 40}})));
  annotation(
    experiment(StartTime = 0, StopTime = 10, Tolerance = 1e-8, Interval = 0.01),
    Documentation(info = "<html>
<p>The benchmark bicycle of Meijaard et al. (2007) (the default parameters of
<code>Bicycle.Bicycles.WhippleLinear</code>) ridden hands-off at 4.6 m/s, inside its self-stable
speed range, after a lateral perturbation that leaves it upright with a roll rate of 0.5 rad/s.
Roll and steer oscillate (weave, about 0.8 Hz) and decay; the bicycle ends in a slow turn
(heading psi and lateral position y keep changing).</p>
</html>"));
end WhippleLinearBenchmark;
