within Bicycle.Mechanics;
package Parts "Rigid bodies and rigid translations"
  extends Bicycle.Icons.Package;
  annotation(Documentation(info = "<html><p>Components that carry mass (<code>RigidBody</code>) or
shift a frame rigidly (<code>FixedTranslation</code>).</p></html>"));
end Parts;
