within Bicycle.Components;
model CrownedRollers "Crowned rollers of lateral (rocking) radius R instead of thin tyres, eq (27)"
  parameter Bicycle.Units.Mass m(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m "Total mass m carried by the rollers";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.g "Gravitational acceleration";
  parameter Bicycle.Units.Length R(min = 0) = Bicycle.Records.Astrom2005SecondOrder.R "Lateral (rocking) radius R of the crowned rollers (R = 0: thin tyres)";
  Bicycle.Interfaces.Roll roll "Roll axis of the frame resting on the rollers";
equation
  // Rolling on the crown moves the contact points R*phi towards the lean: the normal force m*g
  // acting there gives the torque -m*g*R*phi on the frame, so gravity acts with m*g*(h - R)*phi.
  roll.tau = m*g*R*roll.phi;
  annotation(Documentation(info = "<html>
<p>Figure 21: when the bicycle rolls by <code>phi</code> on rollers whose cross-section is a circle
of radius <code>R</code>, the contact points move <code>R*phi</code> to the side of the lean and the
horizontal distance of the centre of mass from them is <code>(h - R)*phi</code>. The gravity term
<code>m*g*h*phi</code> of (1) becomes <code>m*g*(h - R)*phi</code>: the pendulum pole (27)
<code>p = sqrt(m*g*(h - R)/J)</code> is real for <code>R &lt; h</code> and imaginary (an undamped
rocking mode) for <code>R &gt; h</code>. Both wheels are crowned with the same radius, as in (27).</p>
</html>"));
end CrownedRollers;
