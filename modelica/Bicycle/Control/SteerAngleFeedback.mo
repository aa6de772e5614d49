within Bicycle.Control;
block SteerAngleFeedback "Steer-angle feedback for steer-angle-input models, delta = -k2*phi, eq (5)"
  extends Bicycle.Icons.Block;
  parameter Real k2(unit = "1") = 1 "Gain from roll angle to steer angle";
  Bicycle.Interfaces.RealInput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle"
    annotation(Placement(transformation(extent = {{-140, -20}, {-100, 20}})));
  Bicycle.Interfaces.RealOutput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle"
    annotation(Placement(transformation(extent = {{100, -10}, {120, 10}})));
equation
  delta = -k2*phi;
  annotation(
    Icon(graphics = {
      Text(extent = {{-90, 40}, {90, -30}}, textString = "δ = -k2 φ", textColor = {0, 0, 0}),
      Text(extent = {{-150, -150}, {150, -110}}, textString = "k2=%k2", textColor = {0, 0, 0})}),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>Input (<a href=\"modelica://Bicycle.Interfaces.RealInput\">RealInput</a>): <code>phi</code> (roll
angle, rad); output (<a href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a>):
<code>delta</code> (steer angle, rad). The FMU has the same input and output names. Modelica twin of
the Python block <code>SteerAngleFeedback</code> (<code>cosim.cosimulation.controllers</code>).</p>
<p>For the steer-angle-input models of the paper (InvertedPendulum, RearSteered, CrownedRoller):
connect their <code>phi</code> to <code>phi</code> and <code>delta</code> to their
<code>delta</code> (Examples.InvertedPendulumSteerFeedback).</p>
</html>"));
end SteerAngleFeedback;
