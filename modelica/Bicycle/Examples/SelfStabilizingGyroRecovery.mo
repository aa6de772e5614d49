within Bicycle.Examples;
model SelfStabilizingGyroRecovery "Self-stabilizing bicycle with gyroscopic front fork recovering from an initial lean at 4 m/s"
  extends Bicycle.Icons.Example;
  Bicycle.Bicycles.SelfStabilizingGyro bicycle(V = 4, k3 = 0.05, T = 0, frame(phi(start = 0.05))) "Bicycle at 4 m/s, hands off, initial lean 0.05 rad"
    annotation(Placement(transformation(extent = {{-40, -40}, {40, 40}})));
  annotation(
    experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-8, Interval = 0.01),
    Documentation(info = "<html>
<p>No steer torque: the front fork steers into the lean, delta = -k2*phi - k3*der(phi), and the
lean decays. The derivative term k3 adds damping e*k2 + f*k3 to the roll mode of (15).</p>
</html>"));
end SelfStabilizingGyroRecovery;
