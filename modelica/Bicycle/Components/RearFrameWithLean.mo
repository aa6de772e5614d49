within Bicycle.Components;
model RearFrameWithLean "Rear frame carrying an upper body that leans relative to it: roll momentum balance (22) in momentum form"
  extends Bicycle.Components.PartialRearFrame;
  Bicycle.Units.Angle chi(start = 0, fixed = true) "Inertia-weighted roll angle chi = phi + H/J (phi + J_r*theta/J for a leaning rider)";
  Bicycle.Interfaces.LeanInput lean "Lean of the upper body relative to the frame, weighted with its inertia (J_r*theta)"
    annotation(Placement(transformation(origin = {80, 120}, extent = {{-20, -20}, {20, 20}}, rotation = -90)));
equation
  der(chi) = omega;
  phi = chi - lean.H/J;
  annotation(
    Icon(graphics = {
      Text(extent = {{30, -46}, {100, -86}}, textString = "(22)", textColor = {64, 64, 64})}),
    Documentation(info = "<html>
<p>Eq (22), <code>J*der(phi,2) + J_r*der(theta,2) = m*g*h*phi + m_r*g*h_r*theta + ...</code>, contains the
second derivative of the prescribed lean angle <code>theta</code>. Written for the
inertia-weighted roll angle <code>chi = phi + J_r*theta/J</code> it needs no derivative of
<code>theta</code> (index 1):</p>
<pre>  J*der(chi) = L + D*V*delta_f/b
  der(L)     = m*g*h*phi + m*V^2*h/b*delta_f + roll.tau      (roll.tau contains m_r*g*h_r*theta)
  phi        = chi - J_r*theta/J</pre>
<p>The states are <code>L</code> and <code>chi</code>; the roll angle <code>phi</code> of the frame
is algebraic and jumps with a step of <code>theta</code> (the frame rolls against the upper body
so that the total angular momentum is unchanged). <code>omega</code> is <code>der(chi)</code>.</p>
</html>"));
end RearFrameWithLean;
