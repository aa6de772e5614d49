within Bicycle.Control;
block SteerAngleFeedback "Steer-angle feedback for steer-angle-input models, delta = -k2*phi, eq (5)"
  parameter Real k2(unit = "1") = 1 "Gain from roll angle to steer angle";
  Bicycle.Interfaces.RealInput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle";
  Bicycle.Interfaces.RealOutput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle";
equation
  delta = -k2*phi;
  annotation(__Cosim(export = true), Documentation(info = "<html>
<p>Input (<a href=\"modelica://Bicycle.Interfaces.RealInput\">RealInput</a>): <code>phi</code> (roll
angle, rad); output (<a href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a>):
<code>delta</code> (steer angle, rad). The FMU has the same input and output names. Modelica twin of
the Python block <code>SteerAngleFeedback</code> (<code>cosim.cosimulation.controllers</code>).</p>
<p>For the steer-angle-input models of the paper (InvertedPendulum, RearSteered, CrownedRoller):
connect their <code>phi</code> to <code>phi</code> and <code>delta</code> to their
<code>delta</code> (Examples.InvertedPendulumSteerFeedback).</p>
</html>"));
end SteerAngleFeedback;
