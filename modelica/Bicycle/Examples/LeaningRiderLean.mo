within Bicycle.Examples;
model LeaningRiderLean "Self-stabilizing bicycle at 6 m/s steered by the rider leaning the upper body (no steer torque)"
  extends Bicycle.Icons.Example;
  Bicycle.Bicycles.LeaningRider bicycle(V = 6, T = 0, theta = 0.05) "Rider leans the upper body 0.05 rad to the right relative to the frame"
    annotation(Placement(transformation(extent = {{-40, -40}, {40, 40}})));
  annotation(
    experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-8, Interval = 0.01),
    Documentation(info = "<html>
<p>A constant upper-body lean theta with hands off the handlebars (T = 0): at the step the frame
rolls against the upper body (phi jumps by -J_r*theta/J), then the fork and frame settle to a
steady turn, eq (23) with the lean terms as inputs.</p>
</html>"));
end LeaningRiderLean;
