within Bicycle.UsersGuide;
class Variants "How to make another bicycle in a few lines"
  extends Bicycle.Icons.Information;
  annotation(Documentation(info = "<html>
<p>A variant is a model that extends one of the library's bicycles. Keep your variants in a package
of your own, in a folder of your own (called <code>variants</code> here), e.g. as the one file
<code>variants/Mine.mo</code>:</p>
<pre>
package Mine \"My bicycles\"
  model WhippleRollerRear \"benchmark bicycle on a crowned rear roller of lateral radius 0.4 m\"
    extends Bicycle.Bicycles.Whipple(redeclare Bicycle.Wheels.Roller rearWheel(R = 0.4));
    annotation(__Cosim(export = true));
  end WhippleRollerRear;

  model AstromBicycle \"the paper's bicycle with a rigid rider\"
    extends Bicycle.Bicycles.Whipple(redeclare package Data = Bicycle.Records.Astrom2005, c = 0.06);
  end AstromBicycle;
end Mine;
</pre>
<p>Another wheel is one <code>redeclare</code> (the constraining clause keeps radius, mass and
inertia), as in <code>WhippleRollerRear</code>. Toroidal tyres need no redeclare: the default wheels
are tori with crown radii <code>tR</code>, <code>tF</code> (0: knife edge). A wheel that is exactly
a knife edge: <code>redeclare Bicycle.Wheels.KnifeEdge frontWheel</code>.</p>
<p>Another data set is one <code>redeclare package</code>, as in <code>AstromBicycle</code>; every
parameter keeps its name, so single values can still be changed as usual (<code>c = 0.06</code>).
A new data set is a TOML file in <code>cosim/params/</code>, from which the project's records are
generated: <code>python -m cosim.analytic.records --check</code> says whether every record is current,
and the same command without <code>--check</code> writes them. The rider's hinge is replaceable too:
<code>extends Bicycle.Bicycles.WhippleRider(redeclare Bicycle.Mechanics.Rider.LockedHinge hip)</code>
fixes the upper body to the rear frame.</p>
<p>Build and run a variant with <code>--library variants</code>: the folder is searched first, then
the library that ships with cosim (so <code>Bicycle.Bicycles.Whipple</code> is found there):
<code>cosim build Mine.WhippleRollerRear --library variants</code>, then
<code>cosim simulate Mine.WhippleRollerRear --library variants --stop-time 2 --param phi0=0.05</code>.</p>
<p>Instead of <code>--library</code>, the environment variable <code>COSIM_MODELICA_PATH</code> may
name the folder (or several, separated by <code>:</code>). A package is taken from the first folder
that holds it: name yours other than <code>Bicycle</code>, or it hides the shipped library.</p>
</html>"));
end Variants;
