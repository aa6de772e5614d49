within Bicycle.Components;
model SecondOrderRearFrame "Rear frame with rigidly attached rider and wheels: roll momentum balance, eq (1) in momentum form"
  extends Bicycle.Components.PartialRearFrame(phi(start = 0, fixed = true));
  Bicycle.Interfaces.RollRateOutput rollRate "Roll rate der(phi), e.g. for the gyroscopic term of the front fork"
    annotation(Placement(transformation(extent = {{100, -50}, {120, -30}})));
equation
  der(phi) = omega;
  rollRate.omega = omega;
  annotation(
    Icon(graphics = {
      Text(extent = {{30, -46}, {100, -86}}, textString = "(1)", textColor = {64, 64, 64})}),
    Documentation(info = "<html>
<p>States <code>phi</code> and <code>L = J*der(phi) - D*V*delta_f/b</code> (momentum form: the
effective steer angle is algebraic with a static front fork, and an input with a prescribed steer
angle; neither is ever differentiated). Connected to a <code>SteerAngle</code> source it is the
inverted-pendulum model (1); with the <code>StaticFrontFork</code> it is (14) + (11).</p>
</html>"));
end SecondOrderRearFrame;
