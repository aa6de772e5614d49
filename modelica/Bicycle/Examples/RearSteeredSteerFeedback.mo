within Bicycle.Examples;
model RearSteeredSteerFeedback "Rear-steered bicycle (18) under proportional steering delta = -k2*phi: unstable, eq (19)"
  extends Bicycle.Icons.Example;
  parameter Real k2(unit = "1", min = 0) = 0.8 "Gain k2 from roll angle to steer angle";
  Bicycle.Bicycles.RearSteered bicycle(V = 5, phi0 = 0.01) "Rear-steered bicycle at the forward speed 5 m/s, initial lean 0.01 rad to the rider's right"
    annotation(Placement(transformation(extent = {{0, -55}, {80, 25}})));
  Bicycle.Control.SteerAngleFeedback controller(k2 = k2) "Proportional steering delta = -k2*phi"
    annotation(Placement(transformation(extent = {{-80, -35}, {-40, 5}})));
equation
  connect(bicycle.phi, controller.phi) annotation(Line(points = {{84, 9}, {92, 9}, {92, 55}, {-92, 55}, {-92, -15}, {-84, -15}}, color = {0, 0, 127}));
  connect(controller.delta, bicycle.delta) annotation(Line(points = {{-38, -15}, {-8, -15}}, color = {0, 0, 127}));
  annotation(
    experiment(StartTime = 0, StopTime = 3, Tolerance = 1e-8, Interval = 0.01),
    Documentation(info = "<html>
<p>Closed loop (19) at the forward speed V = 5 m/s, in the rider's signs (Bicycles.RearSteered):
<code>J*der(phi,2) - D*V*k2/b*der(phi) + (m*V^2*h*k2/b - m*g*h)*phi = 0</code> has negative damping
for every k2 &gt; 0 and V &gt; 0: the small initial lean grows in an oscillation whose amplitude
increases (poles 0.958 +- 2.96j 1/s for k2 = 0.8). The rider steers into the lean, as on a
front-steered bicycle, where the same feedback balances it
(Examples.InvertedPendulumSteerFeedback).</p>
</html>"));
end RearSteeredSteerFeedback;
