within Bicycle.Mechanics;
package Rider "The rider's upper body on a hip hinge: body, hinges (free with stiffness, damping and lean torque; locked; lean and twist)"
  extends Bicycle.Icons.Package;
  annotation(Documentation(info = "<html>
<p>Components for a rider whose upper body <code>U</code> leans relative to the rear frame
<code>B</code> about a longitudinal hip axis (Astrom, Klein, Lennartsson 2005, \"Effects of Rider
Lean\"), in the generalized coordinates of <a href=\"modelica://Bicycle.Mechanics\">Mechanics</a>:</p>
<ul>
<li><code>UpperBody</code>: the rigid upper body, its centre of mass <code>lU</code> above the hinge axis;</li>
<li><code>PartialHinge</code> (constraining class of the replaceable hinge of
<a href=\"modelica://Bicycle.Bicycles.WhippleRider\">WhippleRider</a>) with <code>HipHinge</code>
(revolute about the frame's x axis with the rider's lean torque as input, a passive spring and
damper), <code>LockedHinge</code> (the upper body held at its initial lean angle;
the lean torque has no effect) and <code>LeanTwistHinge</code> (lean, then twist about the upper
body's vertical axis: two coordinates).</li>
</ul>
<p>Every hinge owns its coordinates; the assembly tells it its column <code>k</code>.</p>
</html>"));
end Rider;
