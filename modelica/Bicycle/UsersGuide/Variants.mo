within Bicycle.UsersGuide;
class Variants "How to make another bicycle in a few lines"
  extends Bicycle.Icons.Information;
  annotation(Documentation(info = "<html>
<p>Another wheel is one <code>redeclare</code> (the constraining clause keeps radius, mass and
inertia):</p>
<pre>
model WhippleRollerRear \"benchmark bicycle on a crowned rear roller of lateral radius 0.4 m\"
  extends Bicycle.Bicycles.Whipple(redeclare Bicycle.Wheels.CrownedRoller rearWheel(R = 0.4));
  annotation(__Cosim(export = true));
end WhippleRollerRear;
</pre>
<p>Toroidal tyres need no redeclare: the default wheels are tori with crown radii <code>tR</code>,
<code>tF</code> (0: knife edge). A wheel that is exactly a knife edge:
<code>redeclare Bicycle.Wheels.KnifeEdge frontWheel</code>.</p>
<p>Another data set is one <code>redeclare package</code>; every parameter keeps its name, so single
values can still be changed as usual:</p>
<pre>
model AstromBicycle \"the paper's bicycle with a rigid rider\"
  extends Bicycle.Bicycles.Whipple(redeclare package Data = Bicycle.Records.Astrom2005, c = 0.06);
end AstromBicycle;
</pre>
<p>A new data set is a TOML file in <code>cosim/params/</code>, from which the project's records are
generated: <code>python -m cosim.analytic.records --check</code> says whether every record is current,
and the same command without <code>--check</code> writes them. The rider's hinge is replaceable too:
<code>extends Bicycle.Bicycles.WhippleRider(redeclare Bicycle.Mechanics.Rider.LockedHinge hip)</code>
fixes the upper body to the rear frame.</p>
<p>To build such a model, save it in a folder of its own, one file per class named after the class,
e.g. the first model above as <code>variants/WhippleRollerRear.mo</code>, and name the folder as a
library (this library stays available):
<code>cosim build WhippleRollerRear --library variants</code>.</p>
</html>"));
end Variants;
