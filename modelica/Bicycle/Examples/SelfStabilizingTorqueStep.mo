within Bicycle.Examples;
model SelfStabilizingTorqueStep "Self-stabilizing bicycle at 6 m/s under a constant steer torque (cf. Figure 5)"
  extends Bicycle.Icons.Example;
  Bicycle.Bicycles.SelfStabilizing bicycle(V = 6) "Self-stabilizing bicycle (14) + (11) at 6 m/s"
    annotation(Placement(transformation(extent = {{0, -40}, {80, 40}})));
  Bicycle.Sources.TorqueStep torque(amplitude = 1, start = 0) "Steer torque of 1 N.m from t = 0 on"
    annotation(Placement(transformation(extent = {{-80, -20}, {-40, 20}})));
equation
  connect(torque.y, bicycle.T) annotation(Line(points = {{-38, 0}, {-8, 0}}, color = {0, 0, 127}));
  annotation(
    experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-8, Interval = 0.01),
    Documentation(info = "<html>
<p>A constant positive steer torque T = 1 N.m, from a source connected to the bicycle's torque
input, gives the inverse response of Figure 5: the path deviation eta is first positive, then
negative; in the steady turn the roll angle is positive and the steer angle negative. Moving
<code>torque.start</code> to a later communication point gives the same response delayed.</p>
</html>"));
end SelfStabilizingTorqueStep;
