within Bicycle.Examples;
model RearSteeredSteerFeedback "Rear-steered bicycle (18) under proportional steering delta = -k2*phi: unstable, eq (19)"
  parameter Real k2(unit = "1", min = 0) = 0.8 "Gain k2 from roll angle to steer angle";
  Bicycle.Bicycles.RearSteered bicycle(V = -5, frame(phi(start = 0.01))) "Rear-steered bicycle at 5 m/s, initial lean 0.01 rad";
  Bicycle.Control.SteerAngleFeedback controller(k2 = k2) "Proportional steering delta = -k2*phi";
equation
  connect(bicycle.phi, controller.phi);
  connect(controller.delta, bicycle.delta);
  annotation(
    experiment(StartTime = 0, StopTime = 3, Tolerance = 1e-8, Interval = 0.01),
    Documentation(info = "<html>
<p>Closed loop (19): <code>J*der(phi,2) - D*|V|*k2/b*der(phi) + (m*V^2*h*k2/b - m*g*h)*phi = 0</code>
has negative damping for every k2 &gt; 0: the small initial lean grows in an oscillation whose
amplitude increases (the same feedback balances the front-steered bicycle,
Examples.InvertedPendulumSteerFeedback).</p>
</html>"));
end RearSteeredSteerFeedback;
